"""JUnit XML: one <testsuite> per drive (a testcase per stage and per check, plus the testcases of
any JUnit file a command check wrote), one <testsuites> for a fleet run."""
import xml.etree.ElementTree as ET


def _case(suite, classname, name, seconds, failure=None, kind="failure"):
    case = ET.SubElement(suite, "testcase", classname=classname, name=name, time=f"{seconds:.3f}")
    if failure is not None:
        ET.SubElement(case, kind, message=failure[:500]).text = failure
    return case


def drive_suite(result):
    name = result["name"]
    suite = ET.Element("testsuite", name=name)
    for st in result.get("stages", []):
        _case(suite, name, st["name"], st["wall_s"],
              None if st["exit"] == 0 else f"{st['name']} exit {st['exit']}: {st.get('tail', '')}", "error")
    for c in result.get("checks", []):
        _case(suite, name, c["name"], c.get("seconds", 0.0), None if c["ok"] else c["message"])
        if c.get("junit"):
            try:
                for case in ET.parse(c["junit"]).getroot().iter("testcase"):
                    case.set("classname", f"{name}.{c['name']}.{case.get('classname', '')}".rstrip("."))
                    suite.append(case)
            except (ET.ParseError, OSError) as e:
                _case(suite, name, f"{c['name']} JUnit", 0.0, f"{c['junit']}: unreadable JUnit XML: {e}", "error")
    for reason in result.get("errors", []):
        _case(suite, name, "drive", 0.0, reason, "error")
    cases = suite.findall("testcase")
    suite.set("tests", str(len(cases)))
    suite.set("failures", str(sum(1 for c in cases if c.find("failure") is not None)))
    suite.set("errors", str(sum(1 for c in cases if c.find("error") is not None)))
    suite.set("time", f"{result.get('wall_s', 0.0):.3f}")
    return suite


def write_drive(result, path):
    ET.ElementTree(drive_suite(result)).write(path, encoding="utf-8", xml_declaration=True)


def write_fleet(results, path):
    root = ET.Element("testsuites", name="meter-fleet")
    for r in results:
        root.append(drive_suite(r))
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)
