"""Writing a :class:`~flexmbd.model.Model` as a SPACAR input file, planar or spatial.

Numbers are written as the shortest text that reads back exactly, so :func:`read_dat` gives back
an equal model. Models that SPACAR's format cannot hold are refused with
:class:`~flexmbd.errors.OutputError`: input laws that are not polynomials
(:class:`~flexmbd.motion.Custom`) and spatial beams without the bending-linked terms.
Rigid beams and lumped masses are written with flexmbd's own keywords ``PLRBEAM`` and
``EMLUMP``. The automatic Euler elements are not written: reading adds them again.
"""

from __future__ import annotations

from pathlib import Path

from ...analysis.integrate import ATOL, RTOL
from ...elements.base import is_translational
from ...engine import MAX_ITERATIONS, load_slots
from ...errors import OutputError
from ...model import CoordinateClass, DeformationClass, Model
from ...motion import Polynomial
from ...settings import RunSettings
from .syntax import LINE_DATA


def _number(value: float) -> str:
    return repr(float(value))  # the shortest text that reads back as the same float


def _line(keyword: str, *values) -> str:
    words = [v if isinstance(v, str) else (str(v) if isinstance(v, int) else _number(v))
             for v in values]
    return " ".join([f"{keyword:<8}", *words]).rstrip()


def dat_text(model: Model, settings: RunSettings | None = None) -> str:
    """The input-file text of ``model`` and, when given, its run ``settings``."""
    lines = [f"# {model.name}: written by flexmbd", "", "# elements"]
    for number, element in sorted(model.elements.items()):
        if not element.type.automatic:
            lines.append(_line(element.type.keyword, number, *element.nodes,
                               *_line_data(number, element)))
    lines += ["", "# initial positions of the translational nodes"]
    for number, node in sorted(model.nodes.items()):
        if is_translational(node.kind) and node.position is not None:
            lines.append(_line("X", number, *node.position))
    lines += ["", "# classification"]
    lines += _classification(model)
    lines += ["END", "HALT", "", "# properties and loads"]
    lines += _properties(model)
    lines += _laws(model)
    settings = settings or RunSettings()
    lines += _settings(settings) + _linear_settings(model, settings)
    transfer = _transfer(settings)
    if transfer:  # SPACAR's transfer-function file: a third block
        lines += ["END", "HALT", "", "# inputs and outputs of the state-space model", *transfer]
    lines += ["END", "END", ""]
    return "\n".join(lines)


def write_dat(model: Model, path: str | Path, settings: RunSettings | None = None) -> Path:
    """Write ``model`` (and its run ``settings``) as a SPACAR input file; returns the path.

    Raises:
        OutputError: the model has a non-polynomial input law, or the file
            cannot be written.
    """
    path = Path(path)
    text = dat_text(model, settings)
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as error:
        raise OutputError(f"cannot write {path}: {error.strerror or error}") from None
    return path


def _line_data(number: int, element) -> list[float]:
    """The element data written after the nodes (a spatial beam's orientation, a spatial
    hinge's axis); refuses data SPACAR's format cannot hold."""
    if element.data.get("bending_linked", (1.0,))[0] == 0.0:
        raise OutputError(f"{element.type.name} {number} leaves out the bending-linked terms, "
                          f"which a SPACAR file cannot say (its BEAM always has them)")
    etype = element.type
    return [v for name in etype.element_data if name in LINE_DATA
            and not (name in etype.optional_data and element.data[name] ==
                     etype.element_data[name])
            for v in element.data[name]]


#: classification keywords of coordinates (by node) and deformations (by element)
_COORDINATE_KEYWORDS = {CoordinateClass.FIXED: "FIX", CoordinateClass.INPUT: "INPUTX",
                        CoordinateClass.DYNAMIC: "DYNX"}
_DEFORMATION_KEYWORDS = {DeformationClass.INPUT: "INPUTE", DeformationClass.DYNAMIC: "DYNE",
                         DeformationClass.RELEASED: "RLSE"}


def _classification(model: Model) -> list[str]:
    lines = []
    for keywords, owners, entries, classes in (
            (_COORDINATE_KEYWORDS, model.nodes, "coordinates", model.coordinate_class),
            (_DEFORMATION_KEYWORDS, model.elements, "deformations", model.deformation_class)):
        for entry_class, keyword in keywords.items():
            for number, owner in sorted(owners.items()):
                ks = [k for k, i in enumerate(getattr(owner, entries), 1)
                      if classes[i] == entry_class]
                if ks:
                    lines.append(_line(keyword, number, *ks))
    return lines


def _properties(model: Model) -> list[str]:
    lines = []
    for number, props in sorted(model.element_properties.items()):
        etype = model.elements[number].type
        if props.mass_per_length or props.section_inertia:
            lines.append(_line("EMLUMP" if props.lumped else "EM", number, props.mass_per_length,
                               *(props.section_inertia or ())))
        for keyword, given, declared in (("ESTIFF", props.stiffness, etype.stiffness_values),
                                         ("EDAMP", props.damping, etype.damping_values)):
            values = [given.get(v.name) for v in declared]
            while values and values[-1] is None:  # values not given (an absent shear term)
                values.pop()
            values = [0.0 if v is None else v for v in values]
            if values:
                lines.append(_line(keyword, number, *values))
        stresses = list(props.prestress or ())
        while stresses and not stresses[-1]:  # SPACAR's ESIG: in order, the rest 0
            stresses.pop()
        if stresses:
            lines.append(_line("ESIG", number, *stresses))
    for number, mass in sorted(model.nodal_masses.items()):
        lines.append(_line("XM", number, mass))
    for number, tensor in sorted(model.nodal_inertias.items()):
        lines.append(_line("XM", number, *tensor))
    for number, load in sorted(model.nodal_forces.items()):
        lines.append(_line("XF", number, *load))
    if any(model.gravity):
        lines.append(_line("GRAVITY", *model.gravity))
    return lines


def _numbers(label: str) -> tuple[int, int]:
    """Node or element number and component of a label: ``"x5.2"`` -> ``(5, 2)``."""
    number, k = label[1:].split(".")
    return int(number), int(k)


def _laws(model: Model) -> list[str]:
    lines = []
    for label, law in sorted(model.input_laws.items()):
        if not isinstance(law, Polynomial):
            raise OutputError(f"the input law of {label} is {type(law).__name__}, which a "
                              f"SPACAR file cannot hold; only Polynomial(x0, v0, a0) laws "
                              f"can be written")
        number, k = _numbers(label)
        keyword = "INPUTX" if label.startswith("x") else "INPUTE"
        lines.append(_line(keyword, number, k, law.x0, law.v0, law.a0))
    return lines


def _settings(settings: RunSettings) -> list[str]:
    lines = []
    for label, (value, rate) in sorted(settings.initial.items()):
        number, k = _numbers(label)
        lines.append(_line("STARTDE" if label.startswith("e") else "STARTDX", number, k,
                           value, rate))
    if settings.t_end is not None:
        lines.append(_line("TIMESTEP", settings.t_end, settings.steps))
    if settings.user_loads:
        lines.append(_line("USERSIG", settings.user_loads))
    if settings.user_inputs:
        lines.append(_line("USERINP", settings.user_inputs))
    if settings.atol is not None or settings.rtol is not None:
        lines.append(_line("ERROR", settings.atol or ATOL, settings.rtol or RTOL))
    if (settings.max_iterations is not None or settings.load_steps is not None
            or settings.tolerance is not None):
        values: list[float] = [settings.max_iterations or MAX_ITERATIONS,
                               settings.load_steps or 1]
        if settings.tolerance is not None:   # the options follow it, as SPACAR reads them
            values += [settings.tolerance, *settings.iteration_options]
        lines.append(_line("ITERSTEP", *values))
    return lines


def _linear_settings(model: Model, settings: RunSettings) -> list[str]:
    """DELXF (every component of the node), DELINPX and DELINPE lines."""
    lines = []
    by_node: dict[int, dict[int, float]] = {}
    for label, value in settings.load_increment.items():
        number, k = _numbers(label)
        by_node.setdefault(number, {})[k] = value
    for number, values in sorted(by_node.items()):
        node = model.nodes[number]
        components = [node.coordinates.index(i) + 1 for i in load_slots(node)]
        lines.append(_line("DELXF", number, *(values.get(k, 0.0) for k in components)))
    for label, delta in sorted(settings.input_increment.items()):
        number, k = _numbers(label)
        lines.append(_line("DELINPX" if label.startswith("x") else "DELINPE", number, k, delta))
    return lines


def _transfer(settings: RunSettings) -> list[str]:
    """The numbered INPUTF, OUTX and OUTXP lines of a transfer-function file's third block,
    the outputs in the settings' order."""
    lines = []
    for i, label in enumerate(settings.force_inputs, 1):
        lines.append(_line("INPUTF", i, *_numbers(label)))
    outputs = settings.output_order or (
        *settings.outputs, *("xd" + label[1:] for label in settings.rate_outputs))
    for i, label in enumerate(outputs, 1):
        rate = label.startswith("xd")
        lines.append(_line("OUTXP" if rate else "OUTX", i,
                           *_numbers(label[1:] if rate else label)))
    return lines
