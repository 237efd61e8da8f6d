"""Ctrl-C is never lost (wingcrack/interrupt.py). Reference: Python's own
behaviour - a KeyboardInterrupt raised inside a finalizer is printed as
"Exception ignored" and dropped; CI once saw a run go on past Ctrl-C that
way. Here the signal is sent from inside a finalizer."""
import gc
import os
import signal

import pytest

from wingcrack import interrupt


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


def _spin():
    for _ in range(1000):   # bytecodes: a pending Python signal handler runs here
        pass


class _TermFinalizer:
    def __del__(self):
        os.kill(os.getpid(), signal.SIGTERM)
        _spin()


def test_sigterm_is_an_interrupt_of_its_own_kind(capfd):
    """Issue 12.9: within a run SIGTERM raises Terminated, a KeyboardInterrupt
    (so every path that stops a run on Ctrl-C stops it on SIGTERM), is never
    lost in a finalizer either, and gives its own status and exit code."""
    with interrupt.watching():
        with pytest.raises(interrupt.Terminated):
            os.kill(os.getpid(), signal.SIGTERM)
            _spin()
        _TermFinalizer()
        gc.collect()
        with pytest.raises(interrupt.Terminated):
            interrupt.check()
        with pytest.raises(interrupt.Terminated):
            with interrupt.deferred():
                os.kill(os.getpid(), signal.SIGTERM)
                _spin()
                reached = True
        assert reached
    assert "Exception ignored" not in capfd.readouterr().err
    assert issubclass(interrupt.Terminated, KeyboardInterrupt)
    assert interrupt.stop_status(interrupt.Terminated()) == "stopped: terminated"
    assert interrupt.stop_status(KeyboardInterrupt()) == "stopped: interrupted"
    # what a shell reports for a process ended by the signal: 128 + its number
    assert interrupt.exit_code(interrupt.Terminated()) == 128 + 15 == 143
    assert interrupt.exit_code(KeyboardInterrupt()) == 128 + 2 == 130


def test_the_sigterm_handler_is_put_back():
    before = signal.getsignal(signal.SIGTERM)
    with interrupt.terminate_raises():
        with pytest.raises(interrupt.Terminated):
            os.kill(os.getpid(), signal.SIGTERM)
            _spin()
        inside = signal.getsignal(signal.SIGTERM)
        with interrupt.watching():
            pass
        assert signal.getsignal(signal.SIGTERM) is inside   # a run gives back the command's handler
    assert signal.getsignal(signal.SIGTERM) == before
