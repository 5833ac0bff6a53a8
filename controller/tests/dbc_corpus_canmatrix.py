#!/usr/bin/python3
"""meter's DBC parser and decoder against python3-canmatrix on every file of a DBC corpus.

usage: dbc_corpus_canmatrix.py METER_CONTROLLER DBC_DIR [--payloads N] [--seed S] [FILE.dbc ...]

For every file: every message (id, extended, name, size, cycle time) and every signal (start bit,
length, byte order, sign, float type, factor, offset, min, max, unit, multiplexor, multiplexer and
multiplexed values, value table) of `meter-controller dump-dbc` equals canmatrix.formats.loadp_flat's
parse, except the divergences listed below where canmatrix is demonstrably wrong. Then for every
message at least N seeded random payloads (multiplexed messages: every other payload carries one of
the switch values the signals use, in turn) decode to the same values with `meter-controller
decode` and canmatrix's Frame.decode. Prints one line per file and every difference; exit 1 on any.
"""
import contextlib
import csv
import io
import json
import logging
import math
import os
import random
import re
import subprocess
import sys
import tempfile
import zlib

import canmatrix
import canmatrix.formats

# Where canmatrix is wrong: (file, message, what differs, reason). Each entry is checked to still
# apply: a divergence that no longer shows up fails the test too.
VAL_NO_SEMICOLON = ("canmatrix drops a VAL_ that lacks its ';' (the next line starts a new statement); "
                    "the table is complete up to the end of its line and meter reads it (missing-semicolon)")
INDEPENDENT = ("canmatrix makes VECTOR__INDEPENDENT_SIG_MSG (the pseudo message of signals that no frame "
               "carries) a frame with id 0; meter, like Vector's tools, defines no frame for it")
BEYOND_FRAME = ("the signal reaches past the message's size: meter decodes it as short_frame (never valid), "
                "canmatrix reads the bits that are not in the frame as if they were")
DIVERGENCES = [
    ("chrysler_pacifica_2017_hybrid_generated.dbc", "ESP_1", "ACC_OFF_REQ", "value table", VAL_NO_SEMICOLON),
    ("chrysler_ram_dt_generated.dbc", "ESP_1", "ACC_OFF_REQ", "value table", VAL_NO_SEMICOLON),
    ("chrysler_ram_hd_generated.dbc", "ESP_1", "ACC_OFF_REQ", "value table", VAL_NO_SEMICOLON),
    ("gm_global_a_powertrain_generated.dbc", "ECMPRDNL2", "ManualMode", "value table", VAL_NO_SEMICOLON),
    ("mazda_2017.dbc", "BSM", "LEFT_BS_STATUS", "value table", VAL_NO_SEMICOLON),
    ("mazda_2017.dbc", "BSM", "RIGHT_BS_STATUS", "value table", VAL_NO_SEMICOLON),
    ("toyota_nodsu_pt_generated.dbc", "CLUTCH", "CLUTCH_RELEASED", "value table", VAL_NO_SEMICOLON),
    ("toyota_tnga_k_pt_generated.dbc", "CLUTCH", "CLUTCH_RELEASED", "value table", VAL_NO_SEMICOLON),
    ("FORD_CADS.dbc", "VECTOR__INDEPENDENT_SIG_MSG", None, "presence", INDEPENDENT),
    ("gm_global_a_object.dbc", "VECTOR__INDEPENDENT_SIG_MSG", None, "presence", INDEPENDENT),
    ("hyundai_2015_mcan.dbc", "VECTOR__INDEPENDENT_SIG_MSG", None, "presence", INDEPENDENT),
    ("ford_lincoln_base_pt.dbc", "INSTRUMENT_PANEL", None, "fd",
     "the only message without its own BA_ VFrameFormat: the file's BA_DEF_DEF_ default is ExtendedCAN_FD, "
     "which canmatrix ignores for is_fd"),
    ("mazda_2017.dbc", "HVAC", "NEW_SIGNAL_4", "decode", BEYOND_FRAME),
    ("mazda_3_2019.dbc", "CAM_KEEP_ALIVE_1", "NEW_SIGNAL_4", "decode", BEYOND_FRAME),
    ("vw_mqb_2010.dbc", "ACC_04", "ACC_Status_Zusatzanz", "value table",
     "the file is UTF-8 and this is its only value table with a non-ASCII letter ('Priorit\\u00e4t'): "
     "canmatrix reads DBC text as cp1252 and, in this file, loses the table (alone in a small file "
     "it garbles the letter to 'Priorit\\u00c3\\u00a4t'); meter reads valid UTF-8 as UTF-8"),
]
# canmatrix drops a BO_ whose id is above 0x7FF without the extended flag (bit 31) and attaches its
# SG_ lines to the message before. meter reads such a message as extended (warning
# standard-id-above-7ff); for those files canmatrix parses a copy with bit 31 set on those ids (in
# the BO_ and in every statement that names them), so the messages are compared too.
ID_REFERENCE = re.compile(r"^(\s*(?:BO_|CM_ BO_|CM_ SG_|CM_|VAL_|SIG_VALTYPE_|SG_MUL_VAL_|BA_ \"[^\"]*\" (?:BO_|SG_)) +)(\d+)\b", re.M)
FD_LENGTHS = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64]


def load_canmatrix(path, md):
    """canmatrix's parse of path (of the copy with bit 31 on 29-bit ids, see ID_REFERENCE)."""
    # canmatrix prints lines it cannot parse to stdout and logs the rest: both are not its parse.
    logging.disable(logging.CRITICAL)
    if any(w["kind"] == "standard-id-above-7ff" for w in md["warnings"]):
        with open(path, "rb") as f:
            text = f.read().decode("cp1252")
        def flag(m):
            i = int(m.group(2))
            return m.group(1) + str(i | 0x80000000 if (i & 0x1FFFFFFF) > 0x7FF and i < 0x80000000 else i)
        with tempfile.NamedTemporaryFile("wb", suffix=".dbc", delete=False) as t:
            t.write(ID_REFERENCE.sub(flag, text).encode("cp1252"))
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                return canmatrix.formats.loadp_flat(t.name)
        finally:
            os.unlink(t.name)
    with contextlib.redirect_stdout(io.StringIO()):
        return canmatrix.formats.loadp_flat(path)


def meter_dump(exe, path):
    out = subprocess.run([exe, "dump-dbc", path], check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def cm_value_type(s):
    if not s.is_float:
        return "integer"
    return "float64" if s.size == 64 else "float32"


def cm_mux(frame, s):
    """(switch name, [[lo, hi], ...]) of a multiplexed canmatrix signal, or None."""
    if s.muxer_for_signal is not None:
        return s.muxer_for_signal, [[int(lo), int(hi)] for lo, hi in s.mux_val_grp]
    if s.mux_val is not None and not (s.is_multiplexer and s.multiplex == "Multiplexor"):
        switch = [x.name for x in frame.signals if x.is_multiplexer and x.muxer_for_signal is None]
        return (switch[0] if switch else None), [[int(s.mux_val), int(s.mux_val)]]
    return None


def same_number(a, b):
    return float(a) == float(b)


def compare_definitions(fname, md, cm, diffs):
    ours = {(m["id"], m["extended"]): m for m in md["messages"]}
    theirs = {(f.arbitration_id.id, bool(f.arbitration_id.extended)): f for f in cm.frames}
    for key in sorted(set(ours) | set(theirs)):
        m, f = ours.get(key), theirs.get(key)
        where = "message 0x%X%s" % (key[0], " (extended)" if key[1] else "")
        if m is None or f is None:
            diffs.append((f.name if f else m["name"], None, "presence",
                          "%s: meter %s, canmatrix %s" % (where, "has it" if m else "-", "has it" if f else "-")))
            continue
        def field(what, a, b, signal=None):
            if a != b:
                diffs.append((m["name"], signal, what, "%s %s%s: meter %r, canmatrix %r" %
                              (where, m["name"], "." + signal if signal else "", a, b)))
        field("name", m["name"], f.name)
        field("size", m["size"], int(f.size))
        field("cycle time", m["cycle_time_ms"] or 0, int(f.cycle_time or 0))
        field("fd", m["fd"], bool(f.is_fd))
        theirs_sig = {s.name: s for s in f.signals}
        field("signal names", sorted(s["name"] for s in m["signals"]), sorted(theirs_sig))
        for s in m["signals"]:
            c = theirs_sig.get(s["name"])
            if c is None:
                continue
            n = s["name"]
            field("start bit", s["start_bit"], c.get_startbit(bit_numbering=1, start_little=c.is_little_endian), n)
            field("length", s["length"], int(c.size), n)
            field("byte order", s["little_endian"], bool(c.is_little_endian), n)
            field("sign", s["signed"], bool(c.is_signed), n)
            field("float type", s["value_type"], cm_value_type(c), n)
            for what in ("factor", "offset"):
                if not same_number(s[what], getattr(c, what)):
                    field(what, s[what], float(getattr(c, what)), n)
            if not same_number(s["minimum"], c.min):
                field("min", s["minimum"], float(c.min), n)
            if not same_number(s["maximum"], c.max):
                field("max", s["maximum"], float(c.max), n)
            field("unit", s["unit"], c.unit, n)
            field("multiplexor", s["multiplexor"], bool(c.is_multiplexer), n)
            ours_mux = [s["mux_switch"], s["mux_ranges"]] if "mux_switch" in s else None
            theirs_mux = cm_mux(f, c)
            field("multiplexing", ours_mux, list(theirs_mux) if theirs_mux else None, n)
            field("value table", {int(v): t for v, t in s["choices"]}, {int(v): t for v, t in c.values.items()}, n)


def put_bits(buf, start, length, little, value):
    """Writes value into buf at a DBC-numbered signal position (Intel: LSB, Motorola: MSB)."""
    pos = start
    for i in range(length):
        bit = (value >> i) & 1 if little else (value >> (length - 1 - i)) & 1
        b = (start + i) if little else pos
        if b // 8 < len(buf):
            buf[b // 8] = (buf[b // 8] & ~(1 << (b % 8))) | (bit << (b % 8))
        if not little:
            pos = pos + 15 if pos % 8 == 0 else pos - 1


def switch_values(msg):
    """The top-level switch signal and the values its multiplexed signals are present for."""
    top = [s for s in msg["signals"] if s["multiplexor"] and "mux_switch" not in s]
    if not top:
        return None, []
    values = set()
    for s in msg["signals"]:
        if s.get("mux_switch") == top[0]["name"]:
            for lo, hi in s["mux_ranges"]:
                values.update(range(lo, min(hi, lo + 15) + 1))
    return top[0], sorted(values)


def payloads(msg, n, rng):
    length = next(x for x in FD_LENGTHS if x >= msg["size"])
    switch, values = switch_values(msg)
    out = []
    for k in range(n):
        p = bytearray(rng.getrandbits(8) for _ in range(length))
        if values and k % 2 == 0:
            put_bits(p, switch["start_bit"], switch["length"], switch["little_endian"], values[(k // 2) % len(values)])
        out.append(bytes(p))
    return out


def compare_decoding(exe, path, md, cm, n, seed, diffs):
    """Returns the number of frames compared."""
    theirs = {(f.arbitration_id.id, bool(f.arbitration_id.extended)): f for f in cm.frames}
    frames = []  # (timestamp text, message json, canmatrix frame, payload)
    for m in md["messages"]:
        f = theirs.get((m["id"], m["extended"]))
        if f is None or not m["signals"] or m["size"] == 0:
            continue
        rng = random.Random(zlib.crc32(("%s/%s/%d" % (os.path.basename(path), m["name"], seed)).encode()))
        for p in payloads(m, n, rng):
            frames.append(("%d.%06d" % divmod(len(frames) + 1, 1000000), m, f, p))
    if not frames:
        return 0
    with tempfile.NamedTemporaryFile("w", suffix=".log", delete=False) as log:
        for ts, m, f, p in frames:
            ident = ("%08X" if m["extended"] else "%03X") % m["id"]
            data = p.hex().upper()
            log.write("(%s) can0 %s%s\n" % (ts, ident, ("##0" + data) if len(p) > 8 else ("#" + data)))
    try:
        out = subprocess.run([exe, "decode", "--dbc", path, log.name], check=True, capture_output=True, text=True).stdout
    finally:
        os.unlink(log.name)
    ours = {}
    for row in csv.DictReader(io.StringIO(out)):
        v = float(row["physical"]) if row["physical"] else math.nan
        ours.setdefault(row["timestamp"], {})[row["signal"]] = v
    reported = 0
    for ts, m, f, p in frames:
        theirs_values = {name: float(d.phys_value) for name, d in f.decode(p).items()}
        mine = ours.get(ts, {})
        offsets = {s["name"]: abs(s["offset"]) + abs(s["factor"]) for s in m["signals"]}
        for name in sorted(set(mine) | set(theirs_values)):
            a, b = mine.get(name), theirs_values.get(name)
            # Both sides scale the raw integer: canmatrix in Decimal (one rounding), meter in double
            # (raw * factor + offset, two roundings): they differ by a few ulp of the largest term,
            # |value| + |offset| bounds it (1e-12 relative is thousands of ulp, far below any LSB).
            scale = max(abs(a or 0), abs(b or 0)) + offsets.get(name, 0)
            close = a is not None and b is not None and (a == b or (math.isnan(a) and math.isnan(b)) or
                                                         abs(a - b) <= 1e-12 * scale)
            if not close and reported < 20:
                reported += 1
                diffs.append((m["name"], name, "decode", "%s %s.%s payload %s: meter %r, canmatrix %r" %
                              (ts, m["name"], name, p.hex(), a, b)))
    return len(frames)


def explained(fname, d):
    for e in DIVERGENCES:
        f, msg, sig, what, _ = e
        if f == fname and msg == d[0] and (sig is None or sig == d[1]) and what == d[2]:
            return e
    return None


def main():
    args = sys.argv[1:]
    n, seed = 100, 1
    if "--payloads" in args:
        i = args.index("--payloads")
        n = int(args[i + 1])
        del args[i:i + 2]
    if "--seed" in args:
        i = args.index("--seed")
        seed = int(args[i + 1])
        del args[i:i + 2]
    exe, corpus = args[0], args[1]
    files = args[2:] or sorted(x for x in os.listdir(corpus) if x.endswith(".dbc"))
    failures, used = 0, set()
    total_frames = 0
    for fname in files:
        path = os.path.join(corpus, fname)
        md = meter_dump(exe, path)
        cm = load_canmatrix(path, md)
        diffs = []
        compare_definitions(fname, md, cm, diffs)
        frames = compare_decoding(exe, path, md, cm, n, seed, diffs)
        total_frames += frames
        unexplained = []
        for d in diffs:
            e = explained(fname, d)
            if e:
                used.add(e)
            else:
                unexplained.append(d)
        nsig = sum(len(m["signals"]) for m in md["messages"])
        print("%s: %d messages, %d signals, %d warnings, %d payloads decoded, %d known divergence(s), %s" %
              (fname, len(md["messages"]), nsig, len(md["warnings"]), frames, len(diffs) - len(unexplained),
               "ok" if not unexplained else "%d DIFFERENCE(S)" % len(unexplained)))
        for d in unexplained[:40]:
            print("  " + d[3])
        failures += bool(unexplained)
    for e in DIVERGENCES:
        if e not in used and e[0] in files:
            print("divergence no longer seen (remove it from the list): %s %s %s %s" % e[:4])
            failures += 1
    print("%d file(s), %d with differences, %d payloads compared" % (len(files), failures, total_frames))
    return 1 if failures else 0


sys.exit(main())
