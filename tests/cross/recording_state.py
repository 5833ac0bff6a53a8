#!/usr/bin/env python3
"""Two link recordings (meter-linkdump / --record lines) carry the same cluster state.

    recording_state.py SERVED RECEIVED

A publisher serving as fast as the link takes them merges deltas, so the receiver sees fewer
messages than were served: what must hold is that the state after the last message is the same,
signal for signal, value and status written exactly (the recordings are lossless), and that every
value received for a signal is one the served recording holds for it. Exit 1 naming the first
difference.
"""
import sys


def messages(path):
    """(type, {signal: "value:status"}) of each SNAPSHOT and DELTA line."""
    out = []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if line.startswith("#") or not line.strip():
                continue
            fields = line.split()
            if len(fields) < 2:
                sys.exit(f"{path}:{number}: expected '(time) TYPE ...', got {line.strip()!r}")
            kind = fields[1]
            if kind not in ("SNAPSHOT", "DELTA"):
                continue
            values = {}
            for field in fields[2:]:
                name, sep, value = field.partition("=")
                if sep and name not in ("seq", "sent", "complete"):
                    values[name] = value
            out.append((kind, values))
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    served, received = (messages(p) for p in sys.argv[1:])
    if not received:
        sys.exit(f"{sys.argv[2]}: no SNAPSHOT or DELTA received")
    final_served, final_received, seen = {}, {}, {}
    for _, values in served:
        final_served.update(values)
        for name, value in values.items():
            seen.setdefault(name, set()).add(value)
    for number, (_, values) in enumerate(received, 1):
        for name, value in values.items():
            # (A signal not yet served is not-available in the receiver's first SNAPSHOT.)
            if value not in seen.get(name, ()) and not value.endswith(":not-available"):
                sys.exit(f"{sys.argv[2]}: message {number}: {name}={value} was never served")
        final_received.update(values)
    for name, value in final_served.items():
        if final_received.get(name) != value:
            sys.exit(f"{sys.argv[2]}: the last state has {name}={final_received.get(name)}, served {value}")
    print(f"recording_state: {len(received)} messages received for {len(served)} served, "
          f"the last state equal in its {len(final_served)} signals")


if __name__ == "__main__":
    main()
