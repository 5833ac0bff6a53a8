#!/usr/bin/python3
"""Writes the E2E attack on vcan0 as a candump -L log (canplayer replays it).

usage: attack_log.py OUT.log
100 genuine SPEED frames at 10 ms (50 km/h, the counter stepping, Toyota checksum), then 20 forged
frames claiming 180 km/h with the next counter but a wrong checksum, then 20 replays of the last
genuine frame (a valid checksum, a repeated counter). The controller must use the first 100 and
refuse the other 40: 20 for the checksum, 20 for the repeated counter.
"""
import sys


def toyota_checksum(can_id, data):
    s = len(data) + (can_id & 0xFF) + (can_id >> 8)
    return (s + sum(data[:-1])) & 0xFF


def frame(speed_kmh, counter, good=True):
    raw = int(speed_kmh * 100)
    data = [raw >> 8, raw & 0xFF, 0, 0, 0, counter & 0x0F, 0, 0]
    data[7] = (toyota_checksum(180, data) + (0 if good else 1)) & 0xFF
    return data


def main():
    t = 1767225600.0
    rows = []
    for i in range(100):
        rows.append(frame(50, i))
    last = rows[-1]
    rows += [frame(180, 100 + i, good=False) for i in range(20)]
    rows += [list(last) for _ in range(20)]
    with open(sys.argv[1], "w") as out:
        for i, data in enumerate(rows):
            out.write("(%.6f) vcan0 0B4#%s\n" % (t + i * 0.01, "".join("%02X" % b for b in data)))


main()
