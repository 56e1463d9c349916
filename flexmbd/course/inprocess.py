"""The in-process confinement of ``--unsafe-in-process``: a Python audit hook (PEP 578)
in the student's own interpreter.

It refuses, in the student's code, writing outside the scratch folder, starting or
signalling processes, network and ``ctypes``, importing flexmbd beyond
:mod:`flexmbd.course.student` and reading flexmbd's files; the runner sets the resource
limits. It is **not** a sandbox: the code it watches shares its interpreter, and reaches
the hook's own data (``gc``, frames), starts processes without an audit event
(``_posixsubprocess``), names paths relative to a directory descriptor, reads other
users' files and the network through what the hook does not see. A graded run uses the
operating-system sandbox (:mod:`flexmbd.course.sandbox`); this is for a grader that has
none and accepts those holes (:data:`OPEN_HOLES`, printed once when it is used).
"""

from __future__ import annotations

import os
import sys

#: what the in-process mode leaves open, said once to the grader who chooses it
OPEN_HOLES = ("--unsafe-in-process: each submission runs in your own user account, guarded "
              "only by an audit hook inside its own Python. A hostile file can get around "
              "it: start unconfined processes (which import flexmbd and compute every "
              "answer), outlive the grading, read the solutions and other students' files, "
              "change or delete files your account may write, and kill the grader. Use it "
              "only for files you trust, or inside a throw-away container per submission "
              "that holds neither flexmbd's solutions nor other submissions.")
#: flexmbd modules a graded file may import: the package (its errors) and the helper
ALLOWED_MODULES = frozenset({"flexmbd", "flexmbd.errors", "flexmbd.course",
                             "flexmbd.course.student"})
#: audit events that start processes or signal them
PROCESS_EVENTS = frozenset({"os.fork", "os.forkpty", "os.system", "os.exec", "os.posix_spawn",
                            "os.spawn", "os.startfile", "subprocess.Popen", "os.kill",
                            "os.killpg", "pty.spawn"})
#: audit events that change the file system, with the argument positions of their paths
PATH_EVENTS = {"os.remove": (0,), "os.rename": (0, 1), "os.rmdir": (0,), "os.mkdir": (0,),
               "os.chmod": (0,), "os.chown": (0,), "os.truncate": (0,), "os.symlink": (1,),
               "os.link": (1,), "os.utime": (0,), "shutil.rmtree": (0,),
               "shutil.copyfile": (1,), "shutil.copytree": (1,), "shutil.move": (1,),
               "shutil.make_archive": (0,), "os.chflags": (0,), "os.setxattr": (0,),
               "os.removexattr": (0,)}
#: audit events of network access and foreign code
FOREIGN_EVENTS = ("socket.", "ctypes.", "_ctypes", "winreg.")
_WRITING = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_APPEND | os.O_TRUNC


def _flexmbd_folders() -> tuple[str, ...]:
    """The folders of flexmbd's files: the package, and its examples (a folder of their own
    in a source checkout)."""
    package = os.path.dirname(os.path.dirname(os.path.realpath(__file__))) + os.sep
    examples = os.path.join(os.path.dirname(package.rstrip(os.sep)), "examples")
    return (package, *((os.path.realpath(examples) + os.sep,)
                       if os.path.isfile(os.path.join(examples, "slider_crank_flex.dat"))
                       else ()))


def confine(scratch: str) -> None:
    """Install the audit hook for the files under ``scratch``."""
    inside = os.path.realpath(scratch) + os.sep
    folders = _flexmbd_folders()
    helper = os.path.join(folders[0], "course", "student.py")

    def within(path) -> bool:
        try:
            return (os.path.realpath(os.fsdecode(path)) + os.sep).startswith(inside)
        except (TypeError, ValueError):
            return False

    def hook(event: str, args: tuple) -> None:
        if event == "import":
            name = str(args[0])
            if (name == "flexmbd" or name.startswith("flexmbd.")) and \
                    name not in ALLOWED_MODULES:
                raise ImportError(f"{name} is not available in a graded check: a graded "
                                  f"answer is your own code (the template imports "
                                  f"flexmbd.course.student only)")
        elif event == "open":
            path, mode, flags = ((*tuple(args), None, None))[:3]
            if isinstance(path, int) or path is None:
                return
            writing = (isinstance(mode, str) and any(c in mode for c in "wax+")) or \
                (isinstance(flags, int) and flags & _WRITING)
            if writing and not within(path):
                raise PermissionError(f"a graded check writes only in its scratch folder, "
                                      f"not {os.fsdecode(path)!r}")
            real = os.path.realpath(os.fsdecode(path))
            if real.startswith(folders) and real != helper:
                raise PermissionError("a graded check may not read flexmbd's files")
        elif event in PROCESS_EVENTS:
            raise PermissionError(f"a graded check may not start or signal processes "
                                  f"({event})")
        elif event in PATH_EVENTS:
            for at in PATH_EVENTS[event]:
                if at < len(args) and isinstance(args[at], str | bytes | os.PathLike) \
                        and not within(args[at]):
                    raise PermissionError(f"a graded check changes only its scratch folder "
                                          f"({event} {os.fsdecode(args[at])!r})")
        elif event.startswith(FOREIGN_EVENTS):
            raise PermissionError(f"a graded check may not use {event.split('.')[0]}")

    sys.addaudithook(hook)
