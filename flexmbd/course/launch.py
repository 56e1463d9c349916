"""Running a student's file: the child process, its channel and its end.

The child is the runner (:mod:`flexmbd.course.runner`), started by a *launcher*:

* :class:`~flexmbd.course.sandbox.Bubblewrap`, the operating-system sandbox of a graded
  run (``isolation="sandbox"``);
* :class:`Unconfined`, a plain child process of the grader's Python in a scratch folder:
  a student's self-check (``"none"``), or with the audit hook of
  :mod:`flexmbd.course.inprocess` (``"in-process"``, which ``--unsafe-in-process`` asks
  for);
* :class:`ContainerCommand`, a command of the lecturer's that starts the runner in a
  container of its own (``--sandbox-command``).

Whatever the launcher, the child reads its request on stdin and answers on stdout, one
JSON record per line, which :mod:`flexmbd.course.channel` reads strictly. A part that
runs out of time or memory, or whose process ends, stops the process; the parts after
it run in a new one. Nothing of a stopped process outlives :func:`run`.
"""

from __future__ import annotations

import contextlib
import json
import os
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from ..errors import ArgumentError, SandboxError
from . import usage
from .channel import Meter, Outcome, Stop, follow
from .sandbox import Bubblewrap, Limits

#: what the grader keeps of a child's stderr (the sandbox's own complaints) [bytes]
STDERR_CAP = 4096
#: the isolation kinds by name
ISOLATIONS = ("sandbox", "in-process", "none")
#: the minimal environment of an unconfined child: what Python and NumPy need
_ENVIRONMENT = {"LANG": "C.UTF-8", "MPLBACKEND": "Agg", "PYTHONDONTWRITEBYTECODE": "1",
                "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "PATH": os.defpath}


#: the children running now, in every thread, by the cancellation event of the grading
#: they belong to (so that an interrupted grading ends its own)
_LIVE: dict = {}
_LIVE_LOCK = threading.Lock()


class Cancelled(Exception):  # noqa: N818 - the grading asked for it, not an error
    """The grading a run belongs to was interrupted: no new process starts."""


class Unconfined:
    """The runner as a child of the grader's own Python, in a scratch folder of its own
    with a minimal environment; ``confine=True`` adds the in-process audit hook and
    limits (:mod:`flexmbd.course.inprocess`), which a hostile file can get around."""

    runner = str(Path(__file__).resolve().with_name("runner.py"))
    path = (str(Path(__file__).resolve().parents[2]),)
    signals_as_status = False

    def __init__(self, limits: Limits | None = None, confine: bool = False) -> None:
        self.limits = limits if limits is not None or not confine else Limits()
        self.confine = "audit-hook" if confine else None
        self.metered = usage.available()   # with limits (in-process) only
        self.name = ("in-process (an audit hook inside the student's Python)" if confine
                     else "unconfined (a self-check)")

    def command(self) -> tuple[list[str], tuple[int, ...]]:
        return [sys.executable, "-I", self.runner], ()


class ContainerCommand:
    """The runner started by ``command``, a container per process: the command must run
    ``python -I /sandbox/lib/flexmbd/course/runner.py`` in a folder it may write, with the
    runner and the student helper at that path (the recipe in the course guide builds
    such an image), keep stdin and stdout attached, and end the container when its first
    process ends."""

    path = ("/sandbox/lib",)
    confine = None
    signals_as_status = True
    metered = False   # its processes are the container engine's, not the grader's

    def __init__(self, command: str, limits: Limits | None = None) -> None:
        self.argv = shlex.split(command)
        if not self.argv:
            raise ArgumentError("--sandbox-command", "is empty")
        self.limits = limits or Limits()
        self.name = f"the lecturer's command {self.argv[0]}"

    def command(self) -> tuple[list[str], tuple[int, ...]]:
        return list(self.argv), ()


def launcher(isolation, limits: Limits | None = None, hide=()):
    """The launcher of an isolation kind (a name of :data:`ISOLATIONS`, or a launcher)."""
    if not isinstance(isolation, str):
        return isolation
    if isolation == "sandbox":
        return Bubblewrap(limits, hide)
    if isolation in ("in-process", "none"):
        return Unconfined(limits, confine=isolation == "in-process")
    raise ArgumentError("isolation", f"choose from {', '.join(ISOLATIONS)}, not "
                                     f"{isolation!r}")


def exit_stop(returncode: int, signals_as_status: bool, limits: Limits | None,
              cpu: float) -> Stop:
    """Why a process ended, from its exit status (a launcher that runs it inside another
    process may report a signal ``n`` as the status ``128 + n``)."""
    number = -returncode if returncode < 0 else (
        returncode - 128 if signals_as_status and 128 < returncode < 160 else None)
    if number is None:
        return Stop("error", f"the file's process exited (status {returncode})")
    name = signal.Signals(number).name if number in signal.Signals._value2member_map_ \
        else f"signal {number}"
    if number == signal.SIGXCPU:
        return Stop("time", f"the file's process used up its CPU time ({cpu:g} s)")
    if number == signal.SIGXFSZ:
        size = f"{limits.file_size / 2**20:g} MB" if limits else "the limit"
        return Stop("error", f"the file's process wrote a file larger than {size}")
    if number == signal.SIGKILL:
        return Stop("killed", "the file's process was killed (SIGKILL: out of memory, or "
                              "the file killed itself)")
    return Stop("killed", f"the file's process crashed ({name})")


class _Drain(threading.Thread):
    """Keeps the first :data:`STDERR_CAP` bytes of a stream and discards the rest."""

    def __init__(self, stream) -> None:
        super().__init__(daemon=True)
        self.stream, self.kept = stream, b""

    def run(self) -> None:
        with contextlib.suppress(OSError, ValueError):
            while chunk := self.stream.read(4096):
                if len(self.kept) < STDERR_CAP:
                    self.kept += chunk[:STDERR_CAP - len(self.kept)]


def _feed(stream, data: bytes) -> None:
    """Write the request to the child's stdin and close it (in a thread: a child that
    does not read must not block the grader)."""
    def write():
        with contextlib.suppress(OSError, ValueError):
            stream.write(data)
        with contextlib.suppress(OSError, ValueError):
            stream.close()
    threading.Thread(target=write, daemon=True).start()


def run(start, name: str, content: bytes, calls: list[dict], part_of: dict,
        timeout: float, cpu: float, cancel: threading.Event | None = None) -> Outcome:
    """Run the file ``content`` (named ``name`` in its scratch folder) on ``calls`` with
    the launcher ``start``, ``timeout`` seconds per part (``part_of``: call id -> part
    letter): a part that runs out of time, or ends the process, is ended with it, and a
    new process runs the parts after it. ``cpu`` is each process's CPU time limit [s].

    Raises:
        Cancelled: ``cancel`` is set (:func:`end_all`).
    """
    outcome = Outcome()
    pending = list(calls)
    while True:   # once at least: a file without calls still loads
        done = _run_once(start, name, content, pending, part_of, timeout, cpu, outcome,
                         cancel)
        if done is None:
            return outcome
        # the part that stopped the process costs itself only: go on after it
        letter = part_of[done]
        pending = [c for c in pending if c["id"] not in outcome.records
                   and part_of[c["id"]] != letter]
        if not pending:
            return outcome


def _run_once(start, name: str, content: bytes, calls: list[dict], part_of: dict,
              timeout: float, cpu: float, outcome: Outcome,
              cancel: threading.Event | None = None) -> int | None:
    """One runner process over ``calls``; returns the id of the call that stopped it
    early, or ``None`` when it ran them all (or never loaded)."""
    header = {"file": name, "size": len(content), "calls": calls, "path": list(start.path),
              "limits": start.limits.for_runner(cpu) if start.limits else None,
              "confine": start.confine}
    argv, fds = start.command()
    scratch = None if isinstance(start, Bubblewrap) else tempfile.mkdtemp(
        prefix="flexmbd-check-")
    environment = dict(os.environ) if isinstance(start, ContainerCommand) else \
        {**_ENVIRONMENT, **({"HOME": scratch, "TMPDIR": scratch} if scratch else {})}
    try:
        try:
            with _LIVE_LOCK:
                if cancel is not None and cancel.is_set():
                    raise Cancelled
                process = subprocess.Popen(argv, cwd=scratch, env=environment,
                                           stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                           stderr=subprocess.PIPE, pass_fds=fds,
                                           start_new_session=True)
                _LIVE[process] = cancel
        except OSError as error:
            raise SandboxError(f"cannot start {start.name}: {error}") from error
        finally:
            for fd in fds:
                os.close(fd)
        stdin, stdout, stderr = process.stdin, process.stdout, process.stderr
        assert stdin is not None and stdout is not None and stderr is not None  # PIPEs
        _feed(stdin, json.dumps(header).encode() + b"\n" + content)
        errors = _Drain(stderr)
        errors.start()
        meter = Meter(process.pid if start.metered and start.limits else None)
        memory = start.limits.memory if start.metered and start.limits else None
        try:
            stopped_in, how, stop = follow(stdout.fileno(), calls, part_of, timeout,
                                            outcome, meter, memory)
            if how == "ended":
                stop = _ending(process, start, (start.limits.cpu if start.limits else None)
                               or cpu)
        finally:
            _end(process)
            with _LIVE_LOCK:
                _LIVE.pop(process, None)
            stdout.close()
            errors.join(timeout=1)
            stderr.close()
        if stop is not None and stopped_in is not None:
            outcome.stopped[stopped_in] = stop
        elif stop is not None and not outcome.loaded:
            outcome.load_stop = stop
            said = errors.kept.decode("utf-8", "replace").strip()
            outcome.problem = ("the file did not finish loading within the time limit"
                               + (f" ({stop.words})" if stop.words else "")
                               if stop.reason == "time" else
                               f"the file's process ended before it finished loading: "
                               f"{stop.words}" + (f" ({said})" if said else ""))
        return stopped_in
    finally:
        if scratch:
            shutil.rmtree(scratch, ignore_errors=True)


def _ending(process, start, cpu: float) -> Stop:
    """Why a process whose channel closed ended: its exit status once it has exited, or
    the closed channel itself when it goes on."""
    try:
        returncode = process.wait(timeout=2)
    except subprocess.TimeoutExpired:
        return Stop("error", "the file closed the channel of its results")
    return exit_stop(returncode, start.signals_as_status, start.limits, cpu)


def end_all(cancel: threading.Event) -> None:
    """Cancel a grading: set ``cancel`` (no run of it starts a process again) and end
    every child of its runs now, instead of waiting for their time limits."""
    with _LIVE_LOCK:
        cancel.set()
        running = [process for process, event in _LIVE.items() if event is cancel]
    for process in running:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(process.pid, signal.SIGKILL)


def _children(pid: int) -> list[int]:
    """The processes ``pid`` started that are still its children (Linux's ``children``
    file; none where the kernel does not keep it)."""
    try:
        text = Path(f"/proc/{pid}/task/{pid}/children").read_text()
    except OSError:
        return []
    return [int(word) for word in text.split()]


def _gone(pid: int) -> bool:
    """Whether ``pid`` has ended (it is gone, or a zombie waiting to be reaped)."""
    try:
        status = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return True
    return status.rpartition(")")[2].split()[:1] == ["Z"]


def _end(process: subprocess.Popen) -> None:
    """End the child and everything it started: its process group here, and with the
    sandbox's first process, the sandbox's whole PID namespace. Returns once the
    namespace's first process is gone: the kernel ends it only after every process of
    its namespace, so nothing of the sandbox outlives this call."""
    inner = _children(process.pid)
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(process.pid, signal.SIGKILL)
    try:
        process.wait(timeout=10)
    except subprocess.TimeoutExpired:   # the group was gone but not its leader
        process.kill()
        process.wait()
    deadline = time.monotonic() + 10
    while inner and time.monotonic() < deadline:
        inner = [pid for pid in inner if not _gone(pid)]
        if inner:
            time.sleep(0.005)


def verify(start) -> None:
    """Run the launcher once on a file that imports NumPy and SciPy.

    Raises:
        SandboxError: it cannot start, or the file does not load in it; the message says
            what to install or which option to give instead.
    """
    if isinstance(start, Bubblewrap) and start.bwrap is None:
        raise SandboxError("grading needs bubblewrap to run each submission in a sandbox "
                           "of its own, and `bwrap` is not installed: install it (Debian "
                           "and Ubuntu: `apt-get install bubblewrap`; Fedora: `dnf install "
                           "bubblewrap`), or run each submission in a container with "
                           "--sandbox-command (see the course guide), or give "
                           "--unsafe-in-process")
    outcome = run(start, "probe.py", b"import numpy, scipy\n", [], {}, 60.0, 60.0)
    if outcome.loaded and not outcome.problem:
        return
    why = outcome.problem or "it did not start"
    raise SandboxError(f"{start.name} does not work here: {why}. Where user namespaces "
                       f"are not allowed (some containers), run each submission in a "
                       f"container with --sandbox-command (see the course guide), or give "
                       f"--unsafe-in-process")
