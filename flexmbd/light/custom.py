"""SPACAR Light's ``opt.customkin`` and ``opt.customdyn``: SPACAR lines added to the model's
input file, honoured as SPACAR reads them.

SPACAR Light writes the lines of ``customkin`` at the end of the file's kinematics block
(after its ``FIX`` lines) and those of ``customdyn`` at the end of its dynamics block
(after ``ITERSTEP``). flexmbd writes the model's file the same way (the one ``opt.filename``
keeps), adds the lines there and reads the file back with its SPACAR reader, so a line
means what it means in any SPACAR file: ``FIX 7 3`` fixes, ``XM 4 0.5`` adds a mass,
``DELXF 4 0 0 -1`` adds a load over the steps. A line the reader refuses is named by its
option and index (``opt.customdyn{2}``, 1-based as in MATLAB). The beams keep their
sections (and so their stresses) unless a line changes their stiffness or mass.
"""

from __future__ import annotations

import dataclasses
import re

from ..errors import ArgumentError, InputFileError
from ..io.dat.reader import dat_from_text
from ..io.dat.writer import dat_text
from ..model import Model
from ..settings import RunSettings
from .build import LightModel

__all__ = ["with_custom_lines"]

#: the settings flexmbd.light takes from the file; a line that changes another (ITERSTEP,
#: TIMESTEP, ...) is SPACAR's run control, which light's own options set
USED_SETTINGS = ("load_increment", "input_increment")


def with_custom_lines(lm: LightModel, settings: RunSettings) -> LightModel:
    """``lm`` with the options' custom lines added to the file of its model and run
    ``settings`` and read back: its model, load and input increments those of the file.

    Raises:
        ArgumentError: a custom line SPACAR's syntax refuses, or one that conflicts with
            the model, named by its option and index.
    """
    kinematic, dynamic = lm.options.customkin, lm.options.customdyn
    own = dat_text(lm.model, settings)
    lines = own.splitlines()
    ends = [i for i, line in enumerate(lines) if line.split()[:1] == ["END"]]
    # inserted from the back, so that the first END's index still holds
    lines[ends[1]:ends[1]] = dynamic
    lines[ends[0]:ends[0]] = kinematic
    first = ends[0] + 1                         # 1-based line of customkin{1}
    named = {first + k: f"opt.customkin{{{k + 1}}}" for k in range(len(kinematic))}
    first = ends[1] + len(kinematic) + 1
    named |= {first + k: f"opt.customdyn{{{k + 1}}}" for k in range(len(dynamic))}
    try:
        # automatic releases (no opt.rls) see the lines too, as SPACAR Light's do
        dat = dat_from_text("\n".join(lines) + "\n", release=lm.options.rls is None)
    except InputFileError as error:
        raise _named_error(error, named, lines) from None
    plain = dat_from_text(own).settings   # the file without the lines
    changed = sorted(name for name in _differing(plain, dat.settings)
                     if name not in USED_SETTINGS)
    if changed:
        lm.notes.append(f"opt.customdyn: {', '.join(changed)} of the SPACAR lines are SPACAR's "
                        f"run control; flexmbd.light steps by its own options (loadsteps) "
                        f"and does not use them")
    model = _with_sections(dat.model, lm.model, lm.notes)
    releases = [_element_and_k(model.deformation_labels[i]) for i in model.released]
    added = sorted(set(releases) - set(lm.releases))
    if added:
        lm.notes.append("with the custom lines, released over-constraints: " + ", ".join(
            f"beam {e} deformation {k}" for e, k in added))
    return dataclasses.replace(lm, model=model, releases=releases,
                               load_increment=dict(dat.settings.load_increment),
                               input_increment=dict(dat.settings.input_increment))


def _element_and_k(label: str) -> tuple[int, int]:
    """``"e12.3"`` -> ``(12, 3)``."""
    element, k = label[1:].split(".")
    return int(element), int(k)


def _differing(plain: RunSettings, read: RunSettings) -> list[str]:
    """The settings (but the notes) that differ between two readings of a file."""
    return [f.name for f in dataclasses.fields(RunSettings) if f.name != "notes"
            and getattr(plain, f.name) != getattr(read, f.name)]


def _named_error(error: InputFileError, named: dict[int, str], lines: list[str]
                 ) -> ArgumentError:
    """The reader's error with its line numbers replaced by the custom lines' names (and
    their text); a line of the model's own file is called that."""
    def name(line: int) -> str:
        if line in named:
            return f"{named[line]} ({lines[line - 1].strip()!r})"
        return f"the model's own line {line} ({lines[line - 1].strip()!r})"

    text = re.sub(r"^line (\d+): ", "", str(error))
    culprit = named.get(error.line or 0)
    if culprit is None:     # the model as a whole, with the lines added
        text = re.sub(r"^[A-Z0-9]+: ", "", text)
    text = re.sub(r"\bline (\d+)", lambda m: name(int(m.group(1))), text)
    if culprit is not None:
        return ArgumentError(culprit, f"{lines[error.line - 1].strip()!r}: {text} "  # type: ignore[operator]
                                      f"(SPACAR lines mean what they mean in a SPACAR file: "
                                      f"see the keyword table of the SPACAR files page)")
    given = list(dict.fromkeys(named[line].split("{")[0] for line in sorted(named)))
    shown = "; ".join(f"{named[line]} {lines[line - 1].strip()!r}" for line in sorted(named))
    return ArgumentError("/".join(given), f"with these lines ({shown}) the model cannot be "
                                          f"built: {text}")


def _with_sections(read: Model, built: Model, notes: list[str]) -> Model:
    """``read`` with the sections and materials of ``built``'s beams where a custom line
    left their stiffness and mass as the section gave them; a changed one loses its
    section (its stresses), as a .dat file's beam has none, and a note says so."""
    properties, lost = dict(read.element_properties), []
    for number, made in built.element_properties.items():
        if made.section is None:
            continue
        plain = dataclasses.replace(made, section=None, material=None)
        if properties.get(number) == plain:
            properties[number] = made
        else:
            lost.append(number)
    if lost:
        notes.append(f"opt.customdyn changes the stiffness or mass of beam"
                     f"{'s' if len(lost) > 1 else ''} {', '.join(map(str, lost))}: "
                     f"{'their' if len(lost) > 1 else 'its'} section no longer describes "
                     f"{'them' if len(lost) > 1 else 'it'}, so no stresses are computed there")
    return dataclasses.replace(read, name=built.name, element_properties=properties)
