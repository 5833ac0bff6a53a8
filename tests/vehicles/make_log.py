#!/usr/bin/python3
"""Writes a candump -L log of a short drive for the Mazda RX-8 DBC of the opendbc corpus, encoded
by python3-canmatrix (an encoder independent of meter's codec).

usage: make_log.py DBC LOG
The drive: 6 s; vehicle and wheel speeds ramp 0 -> 80 km/h and the engine 800 -> 3000 rpm over the
first 4 s, then hold; coolant 90 C, fuel 40 %. 'speed' and 'wheel_speed' every 20 ms, 'coolant'
and 'instrument_cluster' every 100 ms (the DBC gives no cycle times; these are typical).
"""
import decimal
import sys

import canmatrix.formats

T0 = 1767225600.0  # 2026-01-01 00:00:00 UTC
DURATION_S = 6.0


def profile(t):
    ramp = min(t, 4.0) / 4.0
    return {"speed_kmh": 80.0 * ramp, "rpm": 800.0 + 2200.0 * ramp}


def main():
    dbc, out = sys.argv[1], sys.argv[2]
    db = list(canmatrix.formats.loadp(dbc).values())[0]
    fr = {f.name: f for f in db.frames}
    lines = []
    for k in range(int(DURATION_S / 0.02) + 1):
        t = k * 0.02
        p = profile(t)
        msgs = [("speed", {"EngineRPM": p["rpm"], "VehicleSpeed": p["speed_kmh"], "AcceleratorPos": 20}),
                ("wheel_speed", {n: p["speed_kmh"] for n in ("WheelSpeedFL", "WheelSpeedFR", "WheelSpeedRL", "WheelSpeedRR")})]
        if k % 5 == 0:
            msgs += [("coolant", {"CoolantTemperature": 90}),
                     ("instrument_cluster", {"FuelLevel": 40.0, "FuelTankSensorLeft": 100, "FuelTankSensorRight": 100})]
        for i, (name, values) in enumerate(msgs):
            # Frame.encode() packs raw values; phys2raw applies the DBC's factor and offset.
            frame = fr[name]
            raw = {n: frame.signal_by_name(n).phys2raw(decimal.Decimal(repr(v))) for n, v in values.items()}
            data = bytes(frame.encode(raw))
            lines.append("(%.6f) can0 %03X#%s\n" % (T0 + t + i * 0.0002, fr[name].arbitration_id.id, data.hex().upper()))
    with open(out, "w") as f:
        f.writelines(lines)


if __name__ == "__main__":
    main()
