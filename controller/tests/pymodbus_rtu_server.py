#!/usr/bin/python3
"""Independent Modbus RTU peer for the controller's Modbus client test (python3-pymodbus, socat).

usage: pymodbus_rtu_server.py DIR PORT

Makes a pseudo-terminal pair with socat, DIR/client (the controller's end) and DIR/server, and
serves on DIR/server with pymodbus's RTU framer, one process for every RTU case of the test:
- unit 1 answers with the registers input_modbus_test.cpp expects (as pymodbus_server.py does);
- unit 2 answers with the same registers plus 1000 in holding register 0 (a second device);
- unit 9 answers, but every response leaves with its CRC's last byte inverted (a wrong frame);
- any other unit is a silent slave: pymodbus ignores requests to units it does not serve.
The same process serves Modbus TCP on 127.0.0.1:PORT with unit 2's registers (a second Modbus
input beside the RTU one).
SIGTERM stops socat and the server.
"""
import asyncio
import ctypes
import logging
import os
import signal
import subprocess
import sys
import time

from pymodbus.datastore import ModbusSequentialDataBlock, ModbusServerContext, ModbusSlaveContext
from pymodbus.factory import ServerDecoder
from pymodbus.server import StartAsyncSerialServer, StartAsyncTcpServer
from pymodbus.transaction import ModbusRtuFramer

work, port = sys.argv[1], int(sys.argv[2])
logging.getLogger("pymodbus").setLevel(logging.CRITICAL)  # the silent unit and SIGTERM are expected
client, server = os.path.join(work, "client"), os.path.join(work, "server")


def die_with_parent():
    ctypes.CDLL(None).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG: socat goes when this does


socat = subprocess.Popen(["socat", f"pty,raw,echo=0,link={client}", f"pty,raw,echo=0,link={server}"],
                         preexec_fn=die_with_parent)


def stop(*_):
    socat.terminate()
    sys.exit(0)


signal.signal(signal.SIGTERM, stop)
for _ in range(200):
    if os.path.exists(server) and os.path.exists(client):
        break
    time.sleep(0.01)

holding = [0xFFFB, 1234, 0xFFFE, 0x7960, 0x0000, 0x4060]  # int16 -5, uint16 1234, int32 -100000, float32 3.5 (low word first)
inputs = [0x0001, 0x1170]  # uint32 70000


def device(first_holding):
    return ModbusSlaveContext(hr=ModbusSequentialDataBlock(0, [first_holding] + holding[1:]),
                              ir=ModbusSequentialDataBlock(0, inputs), zero_mode=True)


slaves = {1: device(holding[0]), 2: device(1000), 9: device(holding[0])}
framer = ModbusRtuFramer(ServerDecoder())


def corrupt_unit_9(response):
    if response.unit_id != 9:
        return response, False
    frame = bytearray(framer.buildPacket(response))
    frame[-1] ^= 0xFF
    return bytes(frame), True


async def serve():
    await asyncio.gather(
        StartAsyncSerialServer(context=ModbusServerContext(slaves=slaves, single=False), framer=ModbusRtuFramer,
                               port=server, baudrate=19200, ignore_missing_slaves=True,
                               response_manipulator=corrupt_unit_9),
        StartAsyncTcpServer(context=ModbusServerContext(slaves=device(1000), single=True), address=("127.0.0.1", port)))


try:
    asyncio.run(serve())
finally:
    socat.terminate()
