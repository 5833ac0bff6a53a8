-- Shift light: lit near each gear's shift point (the low gears shift earlier). The points suit
-- the demo drive (vcan/drivecycle: each gear peaks at 2124, 2380, 2530, 2800, 2940 rpm before its
-- upshift, 6th reaches 3055 rpm at 130 km/h).
-- Inputs: rpm (Vehicle.Powertrain.CombustionEngine.Speed), gear (...Transmission.CurrentGear).
-- Outputs: lamp (a visibility), glow (an emissive colour).
local shift_rpm = {[1] = 2100, [2] = 2350, [3] = 2500, [4] = 2750, [5] = 2900, [6] = 3000}
local ON, OFF = {1.0, 0.2, 0.0}, {0, 0, 0}

function run(IN, OUT)
  local limit = IN.gear.valid and shift_rpm[IN.gear.value]
  local on = limit and IN.rpm.valid and IN.rpm.value >= limit or false
  OUT.lamp = on
  OUT.glow = on and ON or OFF
end
