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
conn, _ = srv.accept()
line = conn.makefile().readline().strip()   # "exit N"
conn.sendall(f"{iface} {line}\n".encode())
# The guest powers off as soon as this exits: wait until the client has read the reply and closed,
# or the reply may still be in the guest's TCP stack or qemu's forwarder when the VM stops (seen on
# a loaded host: the exit code arrived, the reply did not).
conn.shutdown(socket.SHUT_WR)
conn.settimeout(20)
try:
    while conn.recv(4096):
        pass
except OSError:
    pass
conn.close()
sys.exit(int(line.split()[1]))
