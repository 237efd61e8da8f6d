"""Ctrl-C is never lost (propagation/interrupt.py). Reference: Python's own
behaviour - a KeyboardInterrupt raised inside a finalizer is printed as
"Exception ignored" and dropped; CI once saw a run go on past Ctrl-C that
way. Here the signal is sent from inside a finalizer."""
import gc
import os
import signal

import pytest

from wingcrack.propagation import interrupt


class _Finalizer:
    def __del__(self):
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(1000):   # bytecodes inside the finalizer: the handler runs here
            pass


def test_ctrl_c_swallowed_in_a_finalizer_is_raised_at_the_next_check(capfd):
    with interrupt.watching():
        _Finalizer()          # dropped at once: __del__ runs, the interrupt is swallowed
        gc.collect()
        with pytest.raises(KeyboardInterrupt):
            interrupt.check()
        interrupt.check()     # raised once only
    assert "Exception ignored" not in capfd.readouterr().err


def test_deferred_ctrl_c_is_raised_on_leaving():
    with interrupt.watching():
        with pytest.raises(KeyboardInterrupt):
            with interrupt.deferred():
                os.kill(os.getpid(), signal.SIGINT)
                for _ in range(1000):
                    pass          # nothing raised in here
                reached = True
        assert reached


def test_python_handles_ctrl_c_after_a_run():
    with interrupt.watching():
        pass
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
