"""A drive's process logs, read as records: meter-controller and meter-view run with --log json, so
every stderr line is one JSON object (time, level, program, component, message and fields such as
fault, input, file, line, frame; docs/logging.md). A line that is not one (the controller's stats
on stdout, which the drive's log file also holds, or a crash message) is kept as a plain record
of its text."""
import json


def read(path):
    """Every line of the log as a dict; unreadable file: no records."""
    records = []
    try:
        with open(path, errors="replace") as f:
            for line in f:
                line = line.rstrip("\n")
                if not line:
                    continue
                try:
                    r = json.loads(line) if line.startswith("{") else None
                except ValueError:
                    r = None
                records.append(r if isinstance(r, dict) and "message" in r else {"message": line, "plain": True})
    except OSError:
        pass
    return records


def text(record):
    """The record as the plain-text log would have shown it."""
    if record.get("plain"):
        return record["message"]
    return f"{record.get('program', '?')}: {record['message']}"


def tail(records, n):
    return " | ".join(text(r) for r in records[-n:])


def faults(records):
    """The faults a process reported: records carrying a raised `fault` field."""
    return [text(r) for r in records if r.get("fault")]
