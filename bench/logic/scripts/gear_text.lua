-- The gear readout: P, R, N, D or the gear number; "-" while the gear is not known.
-- Input: gear (Vehicle.Powertrain.Transmission.CurrentGear). Output: gear, a text.
local names = {[-1] = "R", [0] = "N", [126] = "P", [127] = "D"}

function run(IN, OUT)
  if not IN.gear.valid then
    OUT.gear = "-"
    return
  end
  OUT.gear = names[IN.gear.value] or string.format("%d", IN.gear.value)
end
