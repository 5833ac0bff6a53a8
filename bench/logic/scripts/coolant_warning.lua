-- Overheat warning from two signals: the coolant lamp only while the engine runs (a hot engine
-- just switched off is not a fault), with hysteresis so it does not flicker at the threshold.
-- Inputs: coolant (Vehicle.Powertrain.CombustionEngine.ECT), rpm. Output: lamp, a visibility.
local hot = false

function run(IN, OUT)
  if not (IN.coolant.valid and IN.rpm.valid) then
    OUT.lamp = nil  -- not known: the lamp's binding decides
    return
  end
  if hot then hot = IN.coolant.value > 110 else hot = IN.coolant.value >= 115 end
  OUT.lamp = hot and IN.rpm.value > 400
end
