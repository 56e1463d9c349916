"""What a graded student's file may do, enforced inside its process: resource limits and
a Python audit hook (PEP 578), which the code it watches cannot remove.

In a graded run the student's code may not

* write, create, delete or rename anything outside its scratch folder;
* start processes (``subprocess``, ``os.system``, ``os.fork``, ``os.exec*``, spawn) or
  signal others;
* open network connections or load C code through ``ctypes``;
* import flexmbd beyond :mod:`flexmbd.course.student` (the helper the templates import),
  nor read flexmbd's files: a graded answer is the student's own;

and it runs under limits of memory, file size and CPU time. A refused action raises
``PermissionError`` (``ImportError`` for an import) in the student's code, so the part
that tried it fails with that message.

This is in-process isolation: it stops accidents and the cheats a student can write in a
few lines, not an attacker who rewrites the interpreter's memory (``gc`` and frame
introspection reach every object, the hook's own data included). Grade untrusted files
in a container (a throw-away user, no network, a read-only file system) when marks are
at stake against such attacks; see the course guide.
"""

from __future__ import annotations

import contextlib
import os
import resource
import sys

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
#: limits of a graded process: address space [bytes], size of a file it writes [bytes]
MEMORY_LIMIT, FILE_LIMIT = 4 * 2**30, 64 * 2**20
_WRITING = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_APPEND | os.O_TRUNC


def limit_resources(cpu_seconds: int | None = None) -> None:
    """Memory, file size, core dumps and (when given) CPU time of this process."""
    for kind, value in ((resource.RLIMIT_AS, MEMORY_LIMIT),
                        (resource.RLIMIT_FSIZE, FILE_LIMIT), (resource.RLIMIT_CORE, 0),
                        *(((resource.RLIMIT_CPU, cpu_seconds),) if cpu_seconds else ())):
        _soft, hard = resource.getrlimit(kind)
        target = value if hard == resource.RLIM_INFINITY else min(value, hard)
        # a limit the system does not let us lower stays as it is
        with contextlib.suppress(ValueError, OSError):
            resource.setrlimit(kind, (target, target))


def _flexmbd_folders() -> tuple[str, ...]:
    """The folders of flexmbd's files: the package, and its examples (a folder of their own
    in a source checkout)."""
    package = os.path.dirname(os.path.dirname(os.path.realpath(__file__))) + os.sep
    examples = os.path.join(os.path.dirname(package.rstrip(os.sep)), "examples")
    return (package, *((os.path.realpath(examples) + os.sep,)
                       if os.path.isfile(os.path.join(examples, "slider_crank_flex.dat"))
                       else ()))


def confine(scratch: str) -> None:
    """Limit this process and install the audit hook for the files under ``scratch``."""
    limit_resources()
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
