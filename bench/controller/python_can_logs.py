#!/usr/bin/env python3
"""python-can's side of the log readers' benchmark (bench/controller/log_readers.cpp).
  python_can_logs.py write DIR CANDUMP   the candump log written as DIR/ft86.asc, .blf, .trc by python-can
  python_can_logs.py read FILE           python-can reads FILE (by its extension); prints "frames seconds"
"""
import os
import sys
import time

os.environ["TZ"] = "UTC"
time.tzset()
import can  # noqa: E402

READERS = {".log": can.CanutilsLogReader, ".asc": can.ASCReader, ".blf": can.BLFReader, ".trc": can.TRCReader}

if sys.argv[1] == "write":
    out, log = sys.argv[2], sys.argv[3]
    messages = list(can.CanutilsLogReader(log))
    for ext, writer in ((".asc", can.ASCWriter), (".blf", can.BLFWriter), (".trc", can.TRCWriter)):
        with writer(os.path.join(out, "ft86" + ext)) as w:
            for m in messages:
                w.on_message_received(m)
else:
    path = sys.argv[2]
    reader = READERS[os.path.splitext(path)[1]]
    t0 = time.process_time()  # CPU time, as meter's side is timed
    n = sum(1 for _ in reader(path))
    print(n, time.process_time() - t0)
