"""Runs where vcan exists: listens on TCP PORT (all addresses), echoes one line back prefixed with
the name of a CAN interface it verified by opening a raw CAN socket on it, then exits with the
code the client asked for. Proves TCP across the VM boundary and exit-code propagation at once."""
import socket
import sys

port = int(sys.argv[1])
iface = sys.argv[2]
can = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
can.bind((iface,))                      # fails unless iface is a real CAN interface
srv = socket.socket()
srv.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
srv.bind(("0.0.0.0", port))
srv.listen(1)
print(f"echo server listening on {port}", flush=True)
# The client acknowledges the reply ("ack") before it closes. A reply lost on its way out of the
# guest (qemu's user-mode forwarder, seen on a loaded host) gets no ack: the server then takes the
# client's next connection and answers again, so the test judges the forwarded port, not one lucky
# packet.
while True:
    conn, _ = srv.accept()
    reader = conn.makefile()
    line = reader.readline().strip()   # "exit N"
    if not line.startswith("exit "):
        conn.close()
        continue
    conn.sendall(f"{iface} {line}\n".encode())
    conn.settimeout(20)
    try:
        acked = reader.readline().strip() == "ack"
    except OSError:
        acked = False
    conn.close()
    if acked:
        sys.exit(int(line.split()[1]))
