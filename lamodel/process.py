"""How a lamodel process starts and ends: the signals that stop it, its exit status after
one, its worker processes ending with it, and its quick exit.

SIGINT (Ctrl-C), SIGTERM and SIGHUP stop a run the same way (:mod:`lamodel.signals`, where
they are caught): during a search, the search ends and its best certified state is
written; at any other moment the command ends at once, its staging folders removed. The
exit status is then 128 + the signal's number, the shell's convention: 130 for SIGINT,
143 for SIGTERM, 129 for SIGHUP.
"""
from __future__ import annotations

import os
import signal
import sys
import threading
import time

from .signals import STOP_SIGNALS, remove_staged, stop_signal

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_NOT_CERTIFIED = 0, 1, 2, 3

#: The exit statuses and the signal behaviour of every command (the epilog of ``--help``).
EXIT_HELP = """exit statuses:
  0    solve: a certified collapse multiplier; study, table1, bridge --adequacy: every
       one certified; compare: the results agree; build, bridge: the file written
  1    compare: the results differ; any command: an internal error, or the results
       could not be written
  2    bad input (one line on stderr naming the file, block or option)
  3    solve: no certified multiplier (also a structure unstable under its dead load);
       study, table1, bridge --adequacy: some variant, wall or position not certified
  130  interrupted by Ctrl-C (SIGINT); 143 by SIGTERM, 129 by SIGHUP (128 + signal)

signals: SIGINT, SIGTERM and SIGHUP stop a run alike. During a search, the search
ends and the best certified state so far is written (solve: the whole result folder;
study: the table of the variants done, the others marked "not run"); at any other
moment the run ends at once. Staging folders are removed and worker processes end."""


def exit_status(signum: int | None = None) -> int:
    """128 + the number of the stop signal that arrived (130 when none is known: Ctrl-C)."""
    signum = signum if signum is not None else stop_signal()
    return 128 + int(signum if signum is not None else signal.SIGINT)


def end_with_parent(poll: float = 0.5):
    """In a worker process: end it (``os._exit``) as soon as its parent is gone, whatever
    ended the parent (even ``kill -9``), so that no worker outlives a solve or holds the
    caller's pipes. A daemon thread watches the parent's id."""
    parent = os.getppid()

    def watch():
        while os.getppid() == parent:
            time.sleep(poll)
        os._exit(1)
    threading.Thread(target=watch, name="lamodel-end-with-parent", daemon=True).start()


def kill_quietly(processes):
    """Kill worker processes (``multiprocessing`` ones or ``Popen``), ignoring those gone."""
    for p in processes:
        try:
            p.kill()
        except (OSError, AttributeError, ValueError):
            pass


def _exit_at_once(signum, frame):
    os._exit(128 + int(signum))


def exit_now(status: int):
    """End a command-line process with ``status`` once its work is done: the atexit
    handlers run and the standard streams are flushed, then the process exits without
    CPython's teardown of every loaded module (0.2 s with pandas, SciPy and HiGHS loaded).
    Every file lamodel writes is complete and synced before this point.

    The usual ``sys.exit(status)`` instead when called from inside another program (a
    test runner's runpy, a notebook: more than the script's top level and the console
    script's wrapper below this call), or while a worker process or a non-daemon thread
    is still there (the usual exit waits for it), unless a stop signal ended the run: its
    workers are then killed."""
    import atexit
    if threading.current_thread() is threading.main_thread():
        # the result is written and the status decided: a stop signal during the teardown
        # (a pending one, or a second Ctrl-C while threads are joined) ends the process at
        # once with its own status, never as a KeyboardInterrupt escaping the interpreter
        for sig in STOP_SIGNALS:
            if signal.getsignal(sig) is not signal.SIG_IGN:
                signal.signal(sig, _exit_at_once)
    depth, frame = 0, sys._getframe(1)
    while frame is not None and depth <= 2:
        depth, frame = depth + 1, frame.f_back
    children = "multiprocessing" in sys.modules and sys.modules["multiprocessing"].active_children()
    # a stopped run has written what it keeps: its workers (an Ipopt pool still building its
    # models, say) and the threads that manage them are ended, not waited for
    stopped = frame is None and stop_signal() is not None
    if stopped:
        kill_quietly(children or [])
        children = []
    busy = not stopped and any(t is not threading.main_thread() and not t.daemon for t in threading.enumerate())
    if frame is not None or busy or children:
        sys.exit(status)
    try:
        atexit._run_exitfuncs()
    finally:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):  # a closed pipe: nothing more can reach it
                pass
        os._exit(status)


def interrupted(prog: str) -> int:
    """Say that a stop signal ended the run; its exit status (:func:`exit_status`)."""
    remove_staged()
    print(f"{prog}: interrupted", file=sys.stderr)
    return exit_status()


def run_reporting(work, prog: str, debug: bool = False) -> int:
    """``work()``'s exit status, every failure turned into one line on stderr: bad input
    (:class:`lamodel.errors.InputError`) ``<prog>: error: ...``, status 2; results that
    cannot be written (:class:`lamodel.errors.OutputError`) likewise, status 1; a stop signal
    ``<prog>: interrupted``, 128 + the signal; anything else ``<prog>: internal error:
    ...``, status 1 (``debug``: with the traceback)."""
    from .errors import InputError, OutputError
    try:
        status = work()
    except KeyboardInterrupt:
        return interrupted(prog)
    except Exception as exc:
        if stop_signal() is not None:  # an import that a signal broke (see watch_signals)
            return interrupted(prog)
        if debug:
            import traceback
            traceback.print_exc()
        if isinstance(exc, InputError):
            print(f"{prog}: error: {' '.join(str(exc).split())}", file=sys.stderr)
            return EXIT_BAD_INPUT
        if isinstance(exc, OutputError):
            print(f"{prog}: error: {exc.strerror or exc}", file=sys.stderr)
            return EXIT_FAILED
        print(f"{prog}: internal error: {type(exc).__name__}: {exc} (run with --debug for the traceback)",
              file=sys.stderr)
        return EXIT_FAILED
    if stop_signal() is not None and status != exit_status():
        # the signal's KeyboardInterrupt was swallowed where Python ignores exceptions (an
        # import lock's callback, a finaliser): the run went on, but it was asked to stop
        return interrupted(prog)
    return status
