"""The one handler of the stop signals (lamodel.signals), in a fresh interpreter each: a signal
that lands in importlib's own code is delivered again outside it, never raised there; a
search's stop is called instead of raising; a run that outlives the grace is ended."""
import os
import signal
import subprocess
import sys
import textwrap

from conftest import ROOT


def _as_a_terminal_starts_it():
    """The stop signals at their defaults (a runner may start the tests with some ignored:
    ``nohup`` ignores SIGHUP, a shell's background job SIGINT, and children inherit that)."""
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, signal.SIG_DFL)


def run(code, timeout=60):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, env=env,
                          timeout=timeout, preexec_fn=_as_a_terminal_starts_it)


def test_a_signal_in_importlibs_code_is_raised_only_once_it_is_left():
    r = run("""
        import signal, sys, time, types
        from lamodel import signals
        signals.watch_signals()
        # a frame of importlib's own code, as the handler would see it while a lock is taken
        frame = sys._getframe()
        importlib_frame = types.SimpleNamespace(f_code=types.SimpleNamespace(co_filename="<frozen importlib._bootstrap>"))
        signals._on_signal(signal.SIGTERM, importlib_frame)   # must not raise there
        print("not raised in importlib", flush=True)
        t = time.monotonic()
        try:
            while time.monotonic() - t < 5:
                time.sleep(0.001)
        except KeyboardInterrupt:
            print(f"raised after {time.monotonic() - t:.3f} s", flush=True)
        print("signals", signals._received)
    """)
    lines = r.stdout.splitlines()
    assert lines[0] == "not raised in importlib", r.stderr
    assert lines[1].startswith("raised after") and float(lines[1].split()[2]) < 1.0, r.stdout + r.stderr
    assert lines[2] == "signals [15]"  # recorded once, not once per delivery


def test_a_signal_during_a_search_calls_its_stop_and_raises_nothing():
    r = run("""
        import os, signal, time
        from lamodel import signals
        signals.watch_signals()
        stopped = []
        caught = signals.catch_sigint(lambda: stopped.append(1))
        os.kill(os.getpid(), signal.SIGHUP)
        time.sleep(0.1)
        signals.restore_sigint(caught)
        print(stopped, signals.stop_signal())
        # a second search of the same run is stopped at once: the run was asked to stop
        caught = signals.catch_sigint(lambda: stopped.append(2))
        signals.restore_sigint(caught)
        print(stopped)
    """)
    assert r.stdout.splitlines() == ["[1] 1", "[1, 2]"], r.stdout + r.stderr


def test_a_run_that_outlives_the_grace_removes_its_staging_folder_and_ends(tmp_path):
    stage = tmp_path / ".o.lamodel-new-1-x"
    r = run(f"""
        import os, signal, time
        from lamodel import signals
        signals.GRACE = 0.5
        signals.watch_signals()
        os.mkdir({str(stage)!r})
        signals.staged({str(stage)!r})
        signals.catch_sigint(lambda: None)   # a search that never stops
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(30)
        print("still here")
    """)
    assert r.returncode == 143 and "still here" not in r.stdout, (r.returncode, r.stdout, r.stderr)
    assert "did not end within 0.5 s of the stop signal" in r.stderr
    assert not stage.exists()


def test_a_command_that_returned_is_not_ended_later_by_the_grace():
    """In a program that runs lamodel's command line in-process (a test runner, a notebook),
    a Ctrl-C the command handled must not end the program GRACE seconds later."""
    r = run("""
        import os, signal, time
        from lamodel import signals
        signals.GRACE = 0.3
        signal.signal(signal.SIGINT, signal.default_int_handler)
        old = signals.watch_signals()
        try:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(5)
        except KeyboardInterrupt:
            pass
        signals.unwatch_signals(old)
        time.sleep(1.0)
        print("still here")
    """)
    assert r.returncode == 0 and r.stdout.strip() == "still here", (r.returncode, r.stdout, r.stderr)
