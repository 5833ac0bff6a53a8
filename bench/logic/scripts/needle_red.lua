-- A needle that turns red above a limit; below it the artist's colour stands (nil).
-- Input: speed (Vehicle.Speed). Output: colour, a base colour.
local RED = {1.0, 0.05, 0.02, 1.0}

function run(IN, OUT)
  OUT.colour = (IN.speed.valid and IN.speed.value > 130) and RED or nil
end
