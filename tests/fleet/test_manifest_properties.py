"""Property tests (python3-hypothesis) of the fleet manifest reader, scripts/fleet/manifest.py: any
JSON value and any bytes as TOML are either a manifest or a ManifestError naming the file, never
another exception; a valid manifest, generated, loads with its drives in order, the defaults
filled in, every path absolute and existing, the same from JSON and from TOML; and every drive
the reader accepts has an output folder inside the run folder. Derandomized: the same examples on
every run, so a failure replays."""
import json
import os
import sys
import tempfile
import unittest

# Hypothesis keeps a cache (its Unicode tables) in a folder of its own: not in the source tree.
os.environ.setdefault("HYPOTHESIS_STORAGE_DIRECTORY", os.path.join(tempfile.gettempdir(), "meter-hypothesis"))
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

SOURCE_DIR = os.environ.get("METER_SOURCE_DIR") or os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(SOURCE_DIR, "scripts"))
from fleet import manifest, results  # noqa: E402

SETTINGS = settings(derandomize=True, database=None, deadline=None, max_examples=100,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-2**70, 2**70) | st.floats(allow_nan=True) | st.text(max_size=12),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=10), inner, max_size=4),
    max_leaves=20)
# Tables shaped like a manifest, with keys and values from the real vocabulary and wrong types mixed in.
field_values = st.one_of(json_values, st.sampled_from(["a.log", "x.map", "s.msp", "egl", "..", ".", "a/b"]),
                         st.lists(st.sampled_from(["a.log", "b=a.log", "missing.log", 3]), max_size=3))
drive_tables = st.dictionaries(st.sampled_from(sorted(manifest.DRIVE_KEYS) + ["bogus"]), field_values, max_size=8)
manifests = st.fixed_dictionaries({}, optional={"defaults": drive_tables,
                                                "drive": st.lists(drive_tables, max_size=3) | json_values})
names = st.text(alphabet="abcXYZ019-_.", min_size=1, max_size=8)


def write(dir_, name, data):
    path = os.path.join(dir_, name)
    with open(path, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)
    return path


def toml_text(value):
    """A generated valid manifest as TOML (strings, numbers, booleans and lists of them only)."""
    def scalar(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, (int, float)):
            return repr(v)
        if isinstance(v, list):
            return "[" + ", ".join(scalar(x) for x in v) + "]"
        return json.dumps(v)
    lines = []
    if value.get("defaults"):
        lines.append("[defaults]")
        lines += [f"{k} = {scalar(v)}" for k, v in value["defaults"].items()]
    for d in value["drive"]:
        lines.append("[[drive]]")
        lines += [f"{k} = {scalar(v)}" for k, v in d.items()]
    return "\n".join(lines) + "\n"


class ManifestProperties(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="meter-manifest-props-")
        for f in ("a.log", "b.log", "x.map", "s.msp", "c.dbc"):
            write(self.dir, f, "")

    def load_or_error(self, path):
        try:
            return manifest.load(path), None
        except manifest.ManifestError as e:
            self.assertTrue(str(e).startswith(os.path.abspath(path) + ":"), f"error does not name the file: {e}")
            return None, e

    def assert_accepted_drives_stay_inside(self, m):
        run_dir = os.path.join(self.dir, "run")
        for d in m["drives"]:
            out = os.path.normpath(results.drive_dir(run_dir, d["name"]))
            self.assertTrue(out.startswith(os.path.join(run_dir, "drives") + os.sep),
                            f"drive {d['name']!r} writes to {out}, outside {run_dir}/drives")

    @SETTINGS
    @given(value=manifests | json_values)
    def test_any_json_is_a_manifest_or_an_error_naming_the_file(self, value):
        path = write(self.dir, "m.json", json.dumps(value))
        m, _ = self.load_or_error(path)
        if m is not None:
            self.assert_accepted_drives_stay_inside(m)

    @SETTINGS
    @given(data=st.binary(max_size=300) | st.text(max_size=300).map(lambda t: t.encode("utf-8")))
    def test_any_bytes_as_toml_are_a_manifest_or_an_error_naming_the_file(self, data):
        self.load_or_error(write(self.dir, "m.toml", data))

    @SETTINGS
    @given(drives=st.lists(st.fixed_dictionaries(
               {"name": names, "logs": st.lists(st.sampled_from(["a.log", "b.log", "bus=a.log"]), min_size=1, max_size=2)},
               optional={"fps": st.integers(1, 240) | st.floats(0.5, 240), "dump_every": st.integers(0, 100),
                         "dbcs": st.lists(st.just("c.dbc"), max_size=1), "duration": st.integers(0, 60),
                         "dump_at": st.lists(st.integers(0, 60) | st.floats(0, 60), max_size=3)}),
               min_size=1, max_size=4, unique_by=lambda d: d["name"]),
           defaults=st.fixed_dictionaries({}, optional={"fps": st.integers(1, 60), "dump_last": st.booleans()}))
    def test_a_valid_manifest_loads_the_same_from_json_and_toml(self, drives, defaults):
        for d in drives:
            d.update({"map": "x.map", "scene": "s.msp"})
        value = {"defaults": defaults, "drive": drives}
        m_json, err = self.load_or_error(write(self.dir, "m.json", json.dumps(value)))
        if all(set(d["name"]) - {"."} for d in drives):
            self.assertIsNone(err, f"a valid manifest was refused: {err}")
        else:
            self.assertIsNotNone(err, "a drive named only with dots was accepted")
            return
        m_toml, err = self.load_or_error(write(self.dir, "m.toml", toml_text(value)))
        self.assertIsNone(err)
        self.assertEqual(m_json["drives"], m_toml["drives"])
        self.assertEqual([d["name"] for d in m_json["drives"]], [d["name"] for d in drives])
        for given_drive, d in zip(drives, m_json["drives"]):
            for key in ("fps", "dump_last"):
                expected = given_drive.get(key, defaults.get(key, {"fps": 10, "dump_last": False}[key]))
                self.assertEqual(d[key], expected, key)
            for spec in d["logs"] + d["dbcs"] + [d["map"], d["scene"]]:
                path = spec.partition("=")[2] if "=" in spec else spec
                self.assertTrue(os.path.isabs(path) and os.path.isfile(path), spec)
        self.assert_accepted_drives_stay_inside(m_json)


if __name__ == "__main__":
    unittest.main()
