"""Shared set-up of the test suite.

The tests are grouped by what they check: unit/ (one piece against its
definition), verification/ (numbers against analytical solutions, published
tables or a second method), command_line/ (the commands, their outputs and
pictures), robustness/ (bad input, random networks, failures kept on disk)
and mpi/ (several processes). The builders they share (builders.py,
references.py, networks.py, processes.py, admissibility_cases.py) sit here,
beside this file, and are importable from every group.
"""
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))
