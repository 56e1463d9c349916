"""The operating-system sandbox a graded submission runs in, made by bubblewrap (``bwrap``).

Every graded process is a fresh process tree in its own user, mount, PID, IPC, network,
UTS and cgroup namespaces, as user 65534 (nobody) with no capabilities and no way to make
further user namespaces. Its file system is built from nothing; it sees

* the system's ``/usr`` (with ``/bin``, ``/lib``, ... and the dynamic linker's cache) and
  the Python installation, read-only, with every ``site-packages`` folder, flexmbd's
  own folders and the grader's folders hidden under empty read-only ones;
* ``/sandbox/site``: NumPy, SciPy, SymPy and Matplotlib with what they need, read-only;
* ``/sandbox/lib/flexmbd/course``: the helper the templates import
  (:mod:`flexmbd.course.student`) and the runner (:mod:`flexmbd.course.runner`),
  read-only, and nothing else of flexmbd;
* ``/scratch``: a private tmpfs of limited size holding a copy of the file, its working
  folder, home and temporary folder;
* its own ``/proc`` (only its own processes) and a minimal read-only ``/dev``.

The root of that file system is read-only. The network namespace has no interface
but a loopback. Limits of memory, CPU time, processes and file size are set by the
runner before the student's code starts (:func:`flexmbd.course.runner.limit`); the wall
clock is the grader's, which ends the sandbox's first process, and the kernel then ends
every process of its PID namespace: nothing of it outlives the grading.

When the grader runs as root, the sandbox must not run as root outside its namespace
either (a root process is exempt from the process limit, and owns every root file). Then
a private mount namespace first binds what the sandbox needs under a folder that user
nobody may enter, and bubblewrap runs as nobody (``unshare``, ``mount`` and ``setpriv``
of util-linux, which Debian and every major distribution install).
"""

from __future__ import annotations

import functools
import glob
import importlib.metadata
import os
import re
import shutil
import site
import sys
import sysconfig
import tempfile
import weakref
from dataclasses import dataclass
from pathlib import Path

from . import usage

#: the distributions a graded file may import, besides the standard library
PACKAGES = ("numpy", "scipy", "sympy", "matplotlib")
#: where they are inside the sandbox
SITE = "/sandbox/site"
#: where the student helper and the runner are inside the sandbox
LIB = "/sandbox/lib"
#: the scratch folder inside the sandbox
SCRATCH = "/scratch"
#: the user and group id a graded process runs as (nobody)
NOBODY = 65534
#: system folders bound read-only (those that exist), or made the links they are
SYSTEM = ("/usr", "/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32")
#: single system files bound read-only (those that exist)
SYSTEM_FILES = ("/etc/ld.so.cache", "/etc/ld.so.conf")
#: the package folders of other Pythons of the system, hidden as the sandbox's own are
SYSTEM_PACKAGES = ("/usr/lib/python3*/*-packages", "/usr/lib64/python3*/*-packages",
                   "/usr/local/lib/python3*/*-packages", "/usr/local/lib64/python3*/*-packages")
#: the stand-in of the package ``flexmbd`` inside the sandbox
STUB = '"""flexmbd inside a graded sandbox: only flexmbd.course.student is here."""\n'


@dataclass(frozen=True)
class Limits:
    """The limits of one graded process.

    Attributes:
        memory: address space [bytes].
        cpu: CPU time [s]; ``None``: set by the check from its time limits.
        processes: processes and threads of the sandbox's user.
        file_size: the largest file it may write [bytes].
        scratch: the size of its scratch folder [bytes].
    """

    memory: int = 2 * 2**30
    cpu: float | None = None
    processes: int = 64
    file_size: int = 64 * 2**20
    scratch: int = 64 * 2**20

    def for_runner(self, cpu: float) -> dict:
        """The limits the runner sets on itself, with ``cpu`` [s] unless given."""
        return {"memory": self.memory, "cpu": self.cpu or cpu, "processes": self.processes,
                "file_size": self.file_size}


def _normalized(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def _requirements(distribution) -> list[str]:
    """The names of what ``distribution`` requires unconditionally of extras."""
    names = []
    for requirement in distribution.requires or []:
        _, _, marker = requirement.partition(";")
        if "extra" in marker:
            continue
        match = re.match(r"\s*([A-Za-z0-9][A-Za-z0-9._-]*)", requirement)
        if match:
            names.append(match.group(1))
    return names


@functools.cache
def package_files(roots: tuple[str, ...] = PACKAGES) -> dict[str, str]:
    """The files of ``roots`` and of what they require, installed: name in the sandbox's
    ``site`` folder (a package, a module, a folder of shared libraries, a ``.dist-info``)
    -> its path. flexmbd and anything not installed are left out."""
    found: dict[str, str] = {}
    seen: set[str] = {"flexmbd"}
    pending = list(roots)
    while pending:
        name = pending.pop()
        if _normalized(name) in seen:
            continue
        seen.add(_normalized(name))
        try:
            distribution = importlib.metadata.distribution(name)
        except importlib.metadata.PackageNotFoundError:
            continue
        pending += _requirements(distribution)
        for file in distribution.files or []:
            top = file.parts[0]
            if top in ("..", "__pycache__") or top.endswith(".pth") or top in found:
                continue
            path = Path(str(distribution.locate_file(top)))
            if path.exists():
                found[top] = str(path)
    return found


def _interpreter() -> str:
    """The Python the sandbox runs: the base interpreter (not a virtualenv's link)."""
    return os.path.realpath(getattr(sys, "_base_executable", None) or sys.executable)


def _within(path: str, roots) -> bool:
    path = os.path.realpath(path)
    return any(path == root or path.startswith(root.rstrip(os.sep) + os.sep) for root in roots)


def _python_roots() -> list[str]:
    """The folders of the Python installation to bind: its prefix (unless under /usr)."""
    prefix = os.path.realpath(sys.base_prefix)
    roots = [] if _within(prefix, ["/usr"]) else [prefix]
    interpreter = _interpreter()
    if not _within(interpreter, ["/usr", *roots]):
        roots.append(os.path.dirname(interpreter))
    return roots


def _hidden(bound: list[str], extra) -> list[str]:
    """The folders under ``bound`` that the sandbox must not see: every folder Python
    imports from besides the standard library, flexmbd's package and checkout, the
    lecturer's solutions, and ``extra`` (the grader's folders)."""
    standard = {os.path.realpath(sysconfig.get_paths()[key]) for key in ("stdlib",
                                                                        "platstdlib")}
    standard.add(os.path.join(os.path.realpath(sysconfig.get_paths()["stdlib"]),
                              "lib-dynload"))
    candidates = [*site.getsitepackages(), site.getusersitepackages(), *sys.path,
                  sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]]
    package = Path(__file__).resolve().parents[1]
    candidates += [str(package), str(package.parent / "lecturer")]
    if os.environ.get("FLEXMBD_SOLUTIONS"):
        candidates.append(os.environ["FLEXMBD_SOLUTIONS"])
    candidates += [str(p) for p in extra]
    # the package folders of the system's other Pythons (Debian's dist-packages, ...)
    for pattern in SYSTEM_PACKAGES:
        candidates += glob.glob(pattern)
    # never a folder that holds what the sandbox runs (a script's folder on sys.path may
    # be the interpreter's)
    needed = [_interpreter(), *standard]
    hidden: list[str] = []
    for candidate in candidates:
        real = os.path.realpath(candidate or ".")
        if real in standard or not os.path.isdir(real) or not _within(real, bound) \
                or any(_within(n, [real]) for n in needed):
            continue
        if real not in hidden and not any(_within(real, [h]) for h in hidden):
            hidden = [h for h in hidden if not _within(h, [real])] + [real]
    return hidden


def helper_files() -> dict[str, bytes]:
    """The files of ``/sandbox/lib``, all of flexmbd a graded run has: path inside ->
    content."""
    course = Path(__file__).resolve().parent
    return {f"{LIB}/flexmbd/__init__.py": STUB.encode(),
            f"{LIB}/flexmbd/course/__init__.py": b'"""The course helper."""\n',
            f"{LIB}/flexmbd/course/student.py": (course / "student.py").read_bytes(),
            f"{LIB}/flexmbd/course/runner.py": (course / "runner.py").read_bytes()}


def _memory_file(name: str, content: bytes) -> int:
    """A descriptor of an anonymous file holding ``content``, read from its start."""
    fd = os.memfd_create(name, 0)
    os.write(fd, content)
    os.lseek(fd, 0, os.SEEK_SET)
    return fd


#: what runs as root before bubblewrap: the bindings of the pairs before ``--``, then the
#: command after it
_STAGING = 'while [ "$1" != "--" ]; do mount --bind "$1" "$2" || exit 126; shift 2; done; ' \
           'shift; exec "$@"'


class Bubblewrap:
    """Starts processes in the sandbox (see the module docstring).

    Args:
        limits: the limits of each process.
        hide: folders (besides flexmbd's and Python's own) that must not be visible even
            where they lie under a bound folder: the grader's submissions and outputs.
    """

    runner = f"{LIB}/flexmbd/course/runner.py"
    path = (LIB, SITE)
    confine = None
    signals_as_status = True   # bwrap exits 128 + n when its command dies of signal n
    name = "sandbox (bubblewrap: own namespaces, user nobody, read-only Python)"

    def __init__(self, limits: Limits | None = None, hide=()) -> None:
        self.limits = limits or Limits()
        self.bwrap = shutil.which("bwrap")
        self.metered = usage.available()   # its processes are in the tree of our child
        self._hide = tuple(hide)
        self._stage: str | None = None

    def _staged(self, sources: list[str]) -> tuple[list[str], dict[str, str]]:
        """As root: the command that binds ``sources`` under a folder nobody may enter, in
        a private mount namespace, then drops to nobody; and where each source then is."""
        if self._stage is None:
            self._stage = tempfile.mkdtemp(prefix="flexmbd-sandbox-")
            os.chmod(self._stage, 0o755)
            weakref.finalize(self, shutil.rmtree, self._stage, True)
        pairs, where = [], {}
        for k, source in enumerate(sources):
            target = os.path.join(self._stage, str(k))
            if not os.path.lexists(target):
                if os.path.isdir(source):
                    os.mkdir(target, 0o755)
                else:
                    Path(target).touch(0o644)
            pairs += [source, target]
            where[source] = target
        prefix = [shutil.which("unshare") or "unshare", "--mount", "--propagation", "private",
                  "--", "/bin/sh", "-c", _STAGING, "sh", *pairs, "--",
                  shutil.which("setpriv") or "setpriv", f"--reuid={NOBODY}",
                  f"--regid={NOBODY}", "--clear-groups", "--"]
        return prefix, where

    def command(self) -> tuple[list[str], tuple[int, ...]]:
        """The command that starts the runner in a new sandbox, and the descriptors it
        must inherit (the caller closes them once the process has started)."""
        if self.bwrap is None:
            raise FileNotFoundError("bwrap")
        roots = _python_roots()
        packages = package_files()
        sources = roots + list(packages.values())
        prefix, where = self._staged(sources) if os.geteuid() == 0 else ([], {})
        args = ["--unshare-user", "--unshare-pid", "--unshare-ipc", "--unshare-net",
                "--unshare-uts", "--unshare-cgroup-try", "--disable-userns",
                "--uid", str(NOBODY), "--gid", str(NOBODY), "--cap-drop", "ALL",
                "--die-with-parent", "--new-session", "--hostname", "sandbox",
                "--clearenv"]
        for name, value in (("PATH", "/usr/bin:/bin"), ("HOME", SCRATCH), ("TMPDIR", SCRATCH),
                            ("LANG", "C.UTF-8"), ("MPLBACKEND", "Agg"),
                            ("PYTHONDONTWRITEBYTECODE", "1"), ("OPENBLAS_NUM_THREADS", "1"),
                            ("OMP_NUM_THREADS", "1"), ("MKL_NUM_THREADS", "1")):
            args += ["--setenv", name, value]
        for folder in SYSTEM:
            if os.path.islink(folder):
                args += ["--symlink", os.readlink(folder), folder]
            elif os.path.isdir(folder):
                args += ["--ro-bind", folder, folder]
        for file in SYSTEM_FILES:
            if os.path.isfile(file):
                args += ["--ro-bind", file, file]
        for root in roots:
            args += ["--ro-bind", where.get(root, root), root]
        for folder in _hidden(["/usr", *roots], self._hide):
            args += ["--tmpfs", folder, "--remount-ro", folder]
        for name, source in packages.items():
            args += ["--ro-bind", where.get(source, source), f"{SITE}/{name}"]
        fds = []
        for inside, content in helper_files().items():
            fds.append(_memory_file(os.path.basename(inside), content))
            args += ["--ro-bind-data", str(fds[-1]), inside]
        args += ["--proc", "/proc", "--dev", "/dev", "--remount-ro", "/dev",
                 "--size", str(self.limits.scratch), "--tmpfs", SCRATCH,
                 "--remount-ro", "/", "--chdir", SCRATCH]
        return [*prefix, self.bwrap, *args, "--", _interpreter(), "-I", self.runner], \
            tuple(fds)

