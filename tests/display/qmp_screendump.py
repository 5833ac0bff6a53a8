"""The host's side of a display in the qemu VM: QMP's screendump of the guest's scanout, read as
raw RGB (a PPM, P6, 8 bits), no Python packages."""
import json
import socket


def screendump(qmp_socket, ppm_path, timeout=30):
    """Writes the guest's current scanout to ppm_path through the QMP socket."""
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
        s.settimeout(timeout)
        s.connect(qmp_socket)
        f = s.makefile("rw")

        def reply():
            while True:
                msg = json.loads(f.readline())
                if "return" in msg:
                    return msg
                if "error" in msg:
                    raise RuntimeError(f"QMP: {msg['error']}")

        json.loads(f.readline())  # the greeting
        for cmd in ({"execute": "qmp_capabilities"},
                    {"execute": "screendump", "arguments": {"filename": ppm_path}}):
            f.write(json.dumps(cmd) + "\n")
            f.flush()
            reply()


def read_ppm(path):
    """(width, height, RGB bytes) of a binary PPM."""
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos)
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P6" or fields[3] != b"255":
        raise ValueError(f"{path}: not an 8-bit binary PPM ({fields})")
    w, h = int(fields[1]), int(fields[2])
    return w, h, data[pos + 1:pos + 1 + w * h * 3]
