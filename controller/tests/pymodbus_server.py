#!/usr/bin/python3
"""Independent Modbus TCP peer for the controller's Modbus client test (python3-pymodbus).

usage: pymodbus_server.py PORT
Serves holding registers 0..5 and input registers 0..1 with the values input_modbus_test.cpp expects.
"""
import sys

from pymodbus.datastore import ModbusSequentialDataBlock, ModbusServerContext, ModbusSlaveContext
from pymodbus.server import StartTcpServer

port = int(sys.argv[1])
holding = [0xFFFB, 1234, 0xFFFE, 0x7960, 0x0000, 0x4060]  # int16 -5, uint16 1234, int32 -100000, float32 3.5 (low word first)
inputs = [0x0001, 0x1170]  # uint32 70000
store = ModbusSlaveContext(hr=ModbusSequentialDataBlock(0, holding), ir=ModbusSequentialDataBlock(0, inputs), zero_mode=True)
StartTcpServer(context=ModbusServerContext(slaves=store, single=True), address=("127.0.0.1", port))
