-- Shift light: lit at an engine speed that depends on the gear (the low gears shift earlier).
-- Inputs: rpm (Vehicle.Powertrain.CombustionEngine.Speed), gear (...Transmission.CurrentGear).
-- Output: glow, an emissive colour.
local shift_rpm = {[1] = 5800, [2] = 6200, [3] = 6400, [4] = 6500, [5] = 6500, [6] = 6500}
local ON, OFF = {1.0, 0.1, 0.05}, {0, 0, 0}

function run(IN, OUT)
  if not (IN.rpm.valid and IN.gear.valid) then
    OUT.glow = OFF
    return
  end
  local limit = shift_rpm[IN.gear.value]
  OUT.glow = (limit and IN.rpm.value >= limit) and ON or OFF
end
