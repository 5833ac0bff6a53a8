"""The fleet manifest: a TOML (or JSON) file listing drives and what to check on each.

Every error names the file, the drive and the field, and what was expected. Paths are relative to
the manifest's own folder. docs/fleet.md has the format; `[defaults]` fills every drive's missing
keys.
"""
import json
import os
import tomllib

DRIVE_KEYS = {
    "name": str, "logs": list, "dbcs": list, "map": str, "catalog": str, "scene": str,
    "backend": str, "size": str, "msaa": int, "fps": (int, float), "dump_every": int,
    "dump_at": list, "dump_last": bool, "duration": (int, float), "video": bool,
    "golden": list, "signal": list, "command": list,
}
GOLDEN_KEYS = {"frame": int, "png": str, "min_psnr": (int, float), "max_abs_diff": int}
SIGNAL_KEYS = {"signal": str, "at": (int, float), "value": (int, float, str), "tolerance": (int, float),
               "status": str}
COMMAND_KEYS = {"name": str, "argv": list, "timeout": (int, float)}
PATH_KEYS = ("map", "catalog", "scene")


class ManifestError(Exception):
    pass


def _type_name(t):
    if isinstance(t, tuple):
        return " or ".join(x.__name__ for x in t)
    return t.__name__


def _check_table(file, where, table, keys, required):
    if not isinstance(table, dict):
        raise ManifestError(f"{file}: {where}: expected a table, got {type(table).__name__}")
    for key, value in table.items():
        if key not in keys:
            raise ManifestError(f"{file}: {where}: unknown key '{key}' (expected one of {', '.join(sorted(keys))})")
        t = keys[key]
        if isinstance(value, bool) and t is not bool and bool not in (t if isinstance(t, tuple) else (t,)):
            raise ManifestError(f"{file}: {where}.{key}: expected {_type_name(t)}, got a boolean")
        if not isinstance(value, t):
            raise ManifestError(f"{file}: {where}.{key}: expected {_type_name(t)}, got {type(value).__name__} {value!r}")
    for key in required:
        if key not in table:
            raise ManifestError(f"{file}: {where}: missing '{key}'")


def _resolve(base, text):
    """A path, or NAME=path (an input or DBC named for several buses), resolved against base."""
    name, sep, path = text.partition("=")
    if not sep:
        name, path = "", text
    full = path if os.path.isabs(path) else os.path.normpath(os.path.join(base, path))
    return f"{name}={full}" if name else full


def _path_of(spec):
    return spec.partition("=")[2] if "=" in spec else spec


def _log_file(spec):
    """A log's file: FILE#N is channel N of FILE (meter-controller's log:FILE#N)."""
    path = _path_of(spec)
    stem, sep, channel = path.rpartition("#")
    return stem if sep and channel.isdigit() and not os.path.isfile(path) else path


def _load_raw(file):
    try:
        with open(file, "rb") as f:
            data = f.read()
    except OSError as e:
        raise ManifestError(f"{file}: cannot read the manifest: {e.strerror}")
    try:
        if file.endswith(".json"):
            return json.loads(data)
        return tomllib.loads(data.decode("utf-8"))
    except (tomllib.TOMLDecodeError, json.JSONDecodeError, UnicodeDecodeError) as e:
        raise ManifestError(f"{file}: not valid {'JSON' if file.endswith('.json') else 'TOML'}: {e}")


def load(file):
    """Returns {'file', 'dir', 'drives': [drive dicts, defaults applied, paths absolute]}."""
    file = os.path.abspath(file)
    raw = _load_raw(file)
    base = os.path.dirname(file)
    if not isinstance(raw, dict):
        raise ManifestError(f"{file}: expected a table at the top")
    for key in raw:
        if key not in ("defaults", "drive"):
            raise ManifestError(f"{file}: unknown top-level key '{key}' (expected defaults, drive)")
    defaults = raw.get("defaults", {})
    _check_table(file, "defaults", defaults, DRIVE_KEYS, [])
    drives_raw = raw.get("drive")
    if not isinstance(drives_raw, list) or not drives_raw:
        raise ManifestError(f"{file}: expected at least one [[drive]]")
    drives, names = [], set()
    for i, d in enumerate(drives_raw):
        where = f"drive[{i}]"
        _check_table(file, where, d, DRIVE_KEYS, [])
        drive = {"fps": 10, "dump_every": 10, "dump_at": [], "dump_last": False, "backend": "egl", "msaa": 4,
                 "duration": 0, "video": False, "golden": [], "signal": [], "command": [], "dbcs": [],
                 "catalog": "", "size": ""}
        drive.update({k: v for k, v in defaults.items()})
        drive.update(d)
        name = drive.get("name", "")
        # The name is the drive's folder in the run: '.' or '..' would be the run's own folders.
        if not name or not all(c.isalnum() or c in "-_." for c in name) or not name.strip("."):
            raise ManifestError(f"{file}: {where}.name: expected a name of letters, digits, '-', '_', '.' "
                                f"(not only dots: it names the drive's folder), got {name!r}")
        where = f"drive '{name}'"
        if name in names:
            raise ManifestError(f"{file}: {where}: the name is used twice")
        names.add(name)
        for key in ("logs", "map", "scene"):
            if not drive.get(key):
                raise ManifestError(f"{file}: {where}: missing '{key}'")
        if not (0 < drive["fps"] <= 240):
            raise ManifestError(f"{file}: {where}.fps: expected 0 < fps <= 240, got {drive['fps']}")
        if drive["dump_every"] < 0:
            raise ManifestError(f"{file}: {where}.dump_every: expected >= 0, got {drive['dump_every']}")
        for key in ("logs", "dbcs"):
            for j, item in enumerate(drive[key]):
                if not isinstance(item, str):
                    raise ManifestError(f"{file}: {where}.{key}[{j}]: expected a path string, got {item!r}")
            drive[key] = [_resolve(base, s) for s in drive[key]]
        for key in PATH_KEYS:
            if drive.get(key):
                drive[key] = _resolve(base, drive[key])
        for j, t in enumerate(drive["dump_at"]):
            if isinstance(t, bool) or not isinstance(t, (int, float)) or t < 0:
                raise ManifestError(f"{file}: {where}.dump_at[{j}]: expected seconds >= 0, got {t!r}")
        for j, g in enumerate(drive["golden"]):
            _check_table(file, f"{where}.golden[{j}]", g, GOLDEN_KEYS, ["frame", "png"])
            if "min_psnr" not in g and "max_abs_diff" not in g:
                raise ManifestError(f"{file}: {where}.golden[{j}]: expected min_psnr and/or max_abs_diff")
            g["png"] = _resolve(base, g["png"])
        for j, s in enumerate(drive["signal"]):
            _check_table(file, f"{where}.signal[{j}]", s, SIGNAL_KEYS, ["signal", "at"])
            if "value" not in s and "status" not in s:
                raise ManifestError(f"{file}: {where}.signal[{j}]: expected value (with tolerance) and/or status")
            if isinstance(s.get("value"), (int, float)) and "tolerance" not in s:
                raise ManifestError(f"{file}: {where}.signal[{j}]: a numeric value needs a tolerance")
        for j, c in enumerate(drive["command"]):
            _check_table(file, f"{where}.command[{j}]", c, COMMAND_KEYS, ["name", "argv"])
            if not c["argv"] or not all(isinstance(a, str) for a in c["argv"]):
                raise ManifestError(f"{file}: {where}.command[{j}].argv: expected a non-empty list of strings")
        for path in [_log_file(spec) for spec in drive["logs"]] + [_path_of(spec) for spec in drive["dbcs"]] + \
                [drive[k] for k in PATH_KEYS if drive.get(k)]:
            if not os.path.isfile(path):
                raise ManifestError(f"{file}: {where}: no such file {path}")
        drives.append(drive)
    return {"file": file, "dir": base, "drives": drives}
