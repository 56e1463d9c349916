"""Recipes for grading elsewhere (``flexmbd exercise recipe``): a Gradescope autograder
that checks each submission in flexmbd's sandbox, and a container image for a grader
whose machine does not allow bubblewrap.

* ``gradescope``: ``setup.sh`` (installs bubblewrap and flexmbd when Gradescope builds
  its image) and ``run_autograder`` (checks the one file in ``submission/`` and writes
  ``results/results.json``); zip them, with a flexmbd wheel if flexmbd is not on the
  package index, as the autograder.
* ``container``: a ``Dockerfile`` and the ``sandbox/`` folder it copies, the runner and
  the student helper, so that ``flexmbd exercise grade --sandbox-command "docker run
  ... flexmbd-sandbox"`` runs each graded process in a container of its own
  (:data:`CONTAINER_COMMAND`).
"""

from __future__ import annotations

import os
import shlex
from importlib import metadata, resources
from pathlib import Path

from ..errors import ArgumentError
from .gradebook import flexmbd_version
from .parts import Exercise
from .sandbox import helper_files

#: the recipes by name
RECIPES = ("gradescope", "container")
#: the command that runs one graded process in the container recipe's image
CONTAINER_COMMAND = ("docker run --rm -i --network none --read-only "
                     "--tmpfs /scratch:rw,size=64m,uid=65534,gid=65534 --pids-limit 64 "
                     "--memory 2g --cpus 1 --cap-drop ALL "
                     "--security-opt no-new-privileges flexmbd-sandbox")


def _template(recipe: str, name: str) -> str:
    return (resources.files("flexmbd.course") / "recipes" / recipe / name).read_text()


def _write(path: Path, text: str, executable: bool = False, force: bool = False) -> Path:
    if path.exists() and not force:
        raise ArgumentError("directory", f"{path} exists; give --force to overwrite it")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    if executable:
        path.chmod(0o755)
    return path


def _pin(name: str) -> str:
    """``==VERSION`` of the distribution installed here, or nothing."""
    try:
        return f"=={metadata.version(name)}"
    except metadata.PackageNotFoundError:
        return ""


def gradescope(exercise: Exercise, directory: str | os.PathLike, options: str = "",
               force: bool = False) -> list[Path]:
    """Write ``setup.sh`` and ``run_autograder`` for ``exercise`` into ``directory``;
    ``options`` are more options of ``flexmbd exercise check`` (``--points a=2``)."""
    directory = Path(directory)
    run = _template("gradescope", "run_autograder").replace("@EXERCISE@", exercise.name) \
        .replace(" @OPTIONS@", "".join(f" {shlex.quote(o)}" for o in shlex.split(options)))
    setup = _template("gradescope", "setup.sh").replace("@VERSION@", flexmbd_version())
    return [_write(directory / "setup.sh", setup, True, force),
            _write(directory / "run_autograder", run, True, force)]


def container(directory: str | os.PathLike, force: bool = False) -> list[Path]:
    """Write the container recipe's ``Dockerfile`` and ``sandbox/`` into ``directory``,
    with the versions of NumPy, SciPy, SymPy and Matplotlib installed here."""
    directory = Path(directory)
    dockerfile = _template("container", "Dockerfile")
    for name in ("numpy", "scipy", "sympy", "matplotlib"):
        dockerfile = dockerfile.replace(f"@{name.upper()}@", _pin(name))
    return [_write(directory / "Dockerfile", dockerfile, force=force),
            *(_write(directory / inside.lstrip("/"), content.decode(), force=force)
              for inside, content in helper_files().items())]
