"""The stop signals of a lamodel run (SIGINT: Ctrl-C, SIGTERM, SIGHUP), caught in one place.

One handler serves every part of lamodel. It records the signal (:func:`stop_signal`),
then acts by what the main thread is doing:

- in a search or a study (:func:`catch_sigint`): it calls the stop the caller gave (the
  search ends at its next check and keeps its best certified state);
- elsewhere on the command line (:func:`watch_signals`): it raises KeyboardInterrupt, so
  the command ends at once, its staging folders removed. **Never in importlib's own
  code**: an exception raised while it takes or gives back its locks can leave a lock
  held, and every other thread's next import then waits for ever (a thread computing the
  lower bound beside the search hung a run so). A signal that lands there is delivered
  again :data:`RETRY` seconds later, until it lands elsewhere (in the body of the module
  being loaded, say, which importlib unwinds cleanly).

The last guard of the command line: a run still alive :data:`GRACE` seconds after its
first stop signal removes its staging folders and exits with 128 + the signal, whatever
it was waiting for.

A signal that arrives before lamodel has loaded this module (the interpreter's first
tens of milliseconds) has its default action: the process ends with the same status.
"""
from __future__ import annotations

import _imp
import _thread
import os
import select
import shutil
import signal
import threading
import time

#: The signals that stop a solve as Ctrl-C does: the search ends, its best certified state
#: is kept (``timeout``, ``docker stop``, systemd and batch schedulers send SIGTERM; a
#: closed terminal sends SIGHUP).
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
#: Seconds before a signal that landed in importlib's own code is delivered again (its lock
#: handling takes microseconds between the modules' bodies: one or two tries).
RETRY = 0.02
#: Seconds a command-line run may take to end after its first stop signal before it is
#: ended at once (ending normally takes well under a second; writing the folder of a
#: 2,000-block wall with its picture a few seconds).
GRACE = 30.0

RAISE = "raise"  # catch_sigint(RAISE): the signal raises KeyboardInterrupt (outside imports)

_received: list = []  # the stop signals that arrived, in order
_stops: list = []     # what the signal does in the searches and studies running, innermost last
_state = {"watching": False, "echo": 0}  # command-line mode; redeliveries under way
_staged: set = set()  # staging folders to remove if the run is ended at once


def stop_signal() -> int | None:
    """The first stop signal (:data:`STOP_SIGNALS`) that arrived since
    :func:`clear_stop_signal`, or None."""
    return _received[0] if _received else None


def clear_stop_signal():
    """Forget the stop signals that arrived (a new run starts)."""
    _received.clear()


def note_stop_signal(signum: int):
    """Record a stop signal (what :func:`stop_signal` answers)."""
    _received.append(int(signum))


def staged(path):
    """A staging folder the run is writing: removed if the run is ended at once (:data:`GRACE`)."""
    _staged.add(os.fspath(path))


def unstaged(path):
    """The staging folder was published or removed."""
    _staged.discard(os.fspath(path))


def remove_staged():
    """Remove the staging folders a stopped run left (one a signal stopped between its
    creation and the ``try`` that removes it)."""
    for path in list(_staged):
        shutil.rmtree(path, ignore_errors=True)
        _staged.discard(path)


# ------------------------------------------------------------------------- the handler
def _in_importlib(frame) -> bool:
    """True while the main thread runs importlib's own code (taking or giving back its
    locks), or some thread holds the global import lock. An exception raised in a module's
    body, while it loads, is safe: importlib gives its locks back as it unwinds."""
    return _imp.lock_held() or (frame is not None and frame.f_code.co_filename.startswith("<frozen importlib"))


def _on_signal(signum, frame):
    if _state["echo"]:  # our own delivery again of a signal already recorded
        _state["echo"] -= 1
    else:
        note_stop_signal(signum)
        if _state["watching"]:
            _Watcher.get().arm(signum)
    stop = _stops[-1] if _stops else RAISE
    if stop is not RAISE:
        stop()
        return
    if _in_importlib(frame) and _Watcher._one is not None:
        _state["echo"] += 1
        _Watcher.get().again(signum)
        return
    raise KeyboardInterrupt


_on_signal.stops_lamodel = True


class _Watcher:
    """The thread that delivers again a signal that landed in an import, and ends a run
    that outlives :data:`GRACE`. The handler talks to it through a pipe: a write is the
    one thing a signal handler can do without taking a lock another part may hold."""

    _one = None

    @classmethod
    def get(cls) -> "_Watcher":
        if cls._one is None:
            cls._one = cls()
        return cls._one

    def __init__(self):
        self._read, self._write = os.pipe()
        threading.Thread(target=self._run, name="lamodel-signals", daemon=True).start()

    def again(self, signum):
        os.write(self._write, bytes([signum]))

    def arm(self, signum):
        os.write(self._write, bytes([128 + signum]))

    def disarm(self):
        """The run ended on its own (its command returned): no end at once any more."""
        os.write(self._write, bytes([0]))

    def _run(self):
        end, first = None, None
        while True:
            wait = None if end is None else max(0.0, end - time.monotonic())
            if not select.select([self._read], [], [], wait)[0]:
                _end_at_once(first)
            byte = os.read(self._read, 1)[0]
            if byte == 0:
                end = None
            elif byte >= 128:
                if end is None:
                    end, first = time.monotonic() + GRACE, byte - 128
            else:
                time.sleep(RETRY)
                if signal.getsignal(byte) is _on_signal:  # not once lamodel's handler is gone
                    _thread.interrupt_main(byte)
                else:
                    _state["echo"] = max(0, _state["echo"] - 1)


def _end_at_once(signum):
    os.write(2, f"lamodel: the run did not end within {GRACE:g} s of the stop signal; ended now\n".encode())
    if os.environ.get("LAMODEL_STACKS"):
        import faulthandler
        faulthandler.dump_traceback(file=2, all_threads=True)
    remove_staged()
    os._exit(128 + int(signum))


def _forget_in_child():
    """A forked worker starts with no watcher, no stops and no staging folders of its own."""
    _Watcher._one = None
    _stops.clear()
    _staged.clear()
    _state.update(watching=False, echo=0)


os.register_at_fork(after_in_child=_forget_in_child)


# ------------------------------------------------------------------ installing it
def watch_signals() -> dict:
    """The command line: SIGINT, SIGTERM and SIGHUP raise KeyboardInterrupt in the main
    thread outside a search (never inside an import), each remembered
    (:func:`stop_signal`), and a run that outlives :data:`GRACE` after one is ended.
    Returns the handlers to put back (:func:`unwatch_signals`). A signal that is ignored
    stays ignored (a shell's background job, ``nohup``); SIGINT is taken only from
    Python's default handler, and nothing is changed outside the main thread."""
    clear_stop_signal()
    if threading.current_thread() is not threading.main_thread():
        return {}
    _Watcher.get()
    old = {}
    for sig in STOP_SIGNALS:
        current = signal.getsignal(sig)
        default = signal.default_int_handler if sig == signal.SIGINT else signal.SIG_DFL
        if current is default:
            old[sig] = signal.signal(sig, _on_signal)
    _state["watching"] = bool(old)
    return old


def unwatch_signals(old: dict):
    """Put back the handlers :func:`watch_signals` replaced."""
    for sig, handler in old.items():
        signal.signal(sig, handler)
    if old:
        _state["watching"] = False
        _Watcher.get().disarm()


def catch_sigint(on_sigint):
    """Let Ctrl-C (SIGINT), SIGTERM and SIGHUP call ``on_sigint()`` instead of ending the
    process (:data:`RAISE`: raise KeyboardInterrupt, outside imports); the signal is
    recorded (:func:`stop_signal`). Returns what :func:`restore_sigint` needs, or None
    when nothing was changed. ``on_sigint`` runs in the signal handler: it must be quick
    and take no lock (``threading.Event().set`` on an event nobody waits on is fine).

    Nothing is changed outside the main thread (Python allows handlers only there), nor
    for a signal that is ignored: a shell starts background jobs with SIGINT ignored so
    that Ctrl-C at the terminal leaves them running, ``nohup`` ignores SIGHUP, and Python
    itself honours both. SIGTERM and SIGHUP are taken over only from their default action
    or from lamodel's own handler: a program that calls lamodel with its own handler
    keeps it, and one whose SIGTERM or SIGHUP had its default action gets it back when
    the work is done (:func:`restore_sigint` delivers it again: the process ends as it
    would have, its workers already stopped). On the command line a signal that arrived
    before the search started stops it at once.
    """
    if threading.current_thread() is not threading.main_thread():
        return None
    if on_sigint is RAISE:
        _Watcher.get()  # started here, never in the handler
    old = {}
    for sig in STOP_SIGNALS:
        current = signal.getsignal(sig)
        if current is signal.SIG_IGN or current is _on_signal:
            continue
        if sig != signal.SIGINT and current not in (signal.SIG_DFL, None) and not getattr(current, "stops_lamodel",
                                                                                         False):
            continue
        old[sig] = signal.signal(sig, _on_signal)
    if not old and not any(signal.getsignal(sig) is _on_signal for sig in STOP_SIGNALS):
        return None
    _stops.append(on_sigint)
    if _state["watching"] and _received and on_sigint is not RAISE:
        on_sigint()  # the run was asked to stop before this search began
    return old, len(_received), on_sigint


def restore_sigint(caught):
    """Put back the handlers :func:`catch_sigint` replaced; a SIGTERM or SIGHUP that
    arrived meanwhile, where its action was the default one, is delivered again."""
    if caught is None:
        return
    old, mark, on_sigint = caught
    if on_sigint in _stops:
        del _stops[len(_stops) - 1 - _stops[::-1].index(on_sigint)]
    for sig, handler in old.items():
        signal.signal(sig, handler)
    for sig in dict.fromkeys(_received[mark:]):
        if sig != signal.SIGINT and old.get(sig) in (signal.SIG_DFL, None) and sig in old:
            signal.raise_signal(sig)
