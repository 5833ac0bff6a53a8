#!/usr/bin/python3
"""Parse every DBC of a folder with python3-canmatrix, all kept in memory; print the CPU seconds taken.

usage: canmatrix_corpus_parse.py DBC_DIR [--none]
The import of canmatrix is outside the timed part; --none parses nothing (the baseline process
whose peak memory the bench subtracts). The child of bench/dbc-corpus (dbc_corpus_bench).
"""
import contextlib
import io
import logging
import os
import sys
import time

with contextlib.redirect_stderr(io.StringIO()):  # "ldf is not supported" and the like
    import canmatrix.formats

logging.disable(logging.CRITICAL)
folder = sys.argv[1]
files = [] if "--none" in sys.argv else sorted(os.path.join(folder, f) for f in os.listdir(folder) if f.endswith(".dbc"))
# CPU time of this process: the machine may be shared, wall time would count the waits.
t0 = time.process_time()
with contextlib.redirect_stdout(io.StringIO()):  # canmatrix prints the lines it cannot parse
    dbs = [canmatrix.formats.loadp_flat(f) for f in files]
seconds = time.process_time() - t0
print("%d %d %.6f" % (len(dbs), sum(len(d.frames) for d in dbs), seconds))
