"""The contract between Python and the compiled core: what crosses the boundary is
checked there, the statuses have one definition, and the fixed buffers of the C are
sized by the generated element sizes."""

import ast
import dataclasses
from pathlib import Path

import numpy as np
import pytest
from flexmbd.examples import slider_crank_flex

import flexmbd as fm
from flexmbd.elements import ELEMENT_TYPES
from flexmbd.engine import _core, codegen, compile_model
from flexmbd.engine.spec import CoreSpec, SpecError
from flexmbd.engine.workspace import OUTPUTS, workspace_of

from .models import slider_crank


@pytest.fixture(scope="module")
def spec() -> CoreSpec:
    return compile_model(slider_crank())


def with_group(spec: CoreSpec, group: str, **arrays) -> CoreSpec:
    """``spec`` with some arrays of one of its groups replaced (checked anew)."""
    return dataclasses.replace(spec, **{group: dataclasses.replace(getattr(spec, group),
                                                                   **arrays)})


def test_a_spec_refuses_an_array_of_the_wrong_length(spec):
    n = len(spec.elements.c_idx)
    with pytest.raises(SpecError, match=f"c_idx has {n - 1} entries, {n} expected"):
        with_group(spec, "elements", c_idx=spec.elements.c_idx[:-1])


def test_a_spec_refuses_an_index_out_of_range(spec):
    dep = spec.classification.dep.copy()
    dep[0] = spec.sizes.nx  # one past the last coordinate
    with pytest.raises(SpecError, match=rf"dep has entries outside \[0, {spec.sizes.nx}\)"):
        with_group(spec, "classification", dep=dep)
    band = spec.systems.dc_rowband.copy()
    band[0] = -1
    with pytest.raises(SpecError, match="dc_rowband has entries outside"):
        with_group(spec, "systems", dc_rowband=band)


def test_a_spec_refuses_offsets_that_do_not_follow_the_kernels(spec):
    """An element whose type says fewer coordinates than its offsets give it would make
    the core's buffers, sized for the type, read past their ends."""
    etype = spec.elements.etype.copy()
    truss = list(ELEMENT_TYPES).index("PLTRUSS")
    etype[etype != truss] = truss
    with pytest.raises(SpecError, match="c_off does not follow the element types' sizes"):
        with_group(spec, "elements", etype=etype)


def test_spec_arrays_are_read_only_copies(spec):
    with pytest.raises(ValueError, match="read-only"):
        spec.elements.c_idx[0] = 0


def test_the_core_takes_only_a_checked_spec(spec):
    with pytest.raises(TypeError, match="CoreSpec"):
        _core.Core(spec.fields())
    assert set(spec.fields()) == set(_core.FIELDS)


def test_the_binding_checks_lengths_and_types(spec):
    core = _core.Core(spec)
    nx = spec.sizes.nx
    with pytest.raises(ValueError, match=f"x: a float64 array of {nx} entries is needed"):
        core.factor(np.zeros(nx + 1))
    with pytest.raises(ValueError, match="dtype mismatch"):
        core.factor(np.zeros(nx, dtype=np.float32))
    with pytest.raises(ValueError, match="outputs: no column"):
        core.prepare(np.zeros(spec.sizes.nq, np.int32), np.zeros((spec.sizes.nq, 3)),
                     {"velocity": np.zeros((1, nx))}, 1, False)


def test_a_spatial_kernel_refuses_planar_gravity():
    beam = list(ELEMENT_TYPES).index("BEAM")
    nc, npar = _core.KERNEL_SIZES[beam][0], _core.KERNEL_SIZES[beam][2]
    with pytest.raises(ValueError, match="g: a float64 array of 3 entries is needed, got 2"):
        _core.kernel(beam, "gravity", np.zeros(nc), np.zeros(npar), None, np.zeros(2),
                     np.zeros(nc))


def test_output_names_are_the_cores():
    assert tuple(OUTPUTS) == _core.OUTPUTS


def test_every_failure_status_has_a_message():
    """Each status of the core's one enum that a run can end with becomes one of
    flexmbd's errors with its own message, never the fallback."""
    engine = workspace_of(slider_crank())
    for status in _core.FmStatus:
        if status in (_core.FmStatus.FM_OK, _core.FmStatus.FM_PARTITION):
            continue
        error = engine.error({"code": status, "time": 0.5, "iterations": 3, "residual": 1.0,
                              "worst": 0, "conditioning": 1e-12, "limit": 1e-4,
                              "step": 1e-3, "exception": ValueError("raised")})
        assert error is not None and "the core stopped" not in str(error), status
    assert engine.error({"code": _core.FmStatus.FM_OK}) is None


def test_the_buffer_sizes_are_generated_from_the_definitions():
    """kernels.h, which sizes the core's fixed buffers, is what the generator makes of
    the element types now (as kernels.c is, see test_elements)."""
    assert codegen.SIZES.read_text() == codegen.sizes_header()
    largest = max(cls.n_coordinates() for cls in ELEMENT_TYPES.values())
    assert f"#define FM_MAX_NC {largest}\n" in codegen.SIZES.read_text()


def test_the_generator_refuses_an_element_too_large_for_the_core(monkeypatch):
    class Huge:
        keyword, reference = "HUGE", 0

        @staticmethod
        def n_coordinates():
            return codegen.MAX_COORDINATES + 1

        @staticmethod
        def n_deformations():
            return 1

        @staticmethod
        def dimension():
            return 3

    monkeypatch.setattr(codegen, "ELEMENT_TYPES", {**ELEMENT_TYPES, "HUGE": Huge})
    with pytest.raises(ValueError, match=f"HUGE: {codegen.MAX_COORDINATES + 1} coordinates"):
        codegen.sizes_header()


def test_a_callback_exception_is_raised_again_with_its_type():
    """A law that raises inside a run comes back as flexmbd's error naming it, its cause
    the user's exception."""
    def law(t):
        if t > 0.5:
            raise ZeroDivisionError("the user's law")
        return (t, 1.0, 0.0)

    model = slider_crank(law=law)
    with pytest.raises(fm.SimulationError, match="ZeroDivisionError") as raised:
        fm.kinematic_analysis(model, np.linspace(0.0, 1.0, 11))
    assert isinstance(raised.value.__cause__, ZeroDivisionError)


def test_one_state_inverse_dynamics_is_a_runs_output():
    """The static Newton iterations' single call (``Workspace.equilibrium``) gives what an
    inverse-dynamics run over a time grid gives at the same state: another path through
    the core (laws, predictor, the run's loads callback)."""
    model = slider_crank_flex.build_model(2, eps1flex=True)
    load = np.linspace(-1.0, 1.0, model.n_coordinates)  # forces and moments everywhere

    def forces(t, x, xd):
        return load

    run = fm.inverse_dynamics(model, np.linspace(0.0, 0.6, 4), forces=forces)
    engine = workspace_of(model)
    for k in range(len(run.t)):
        state = engine.equilibrium(run.q[k], run.qd[k], run.qdd[k], run.x[k], load)
        for name in ("x", "xdd", "sigma", "reactions", "driving"):
            np.testing.assert_allclose(state[name][0], getattr(run, name)[k], rtol=1e-9,
                                       atol=1e-9, err_msg=name)


def test_the_stub_declares_exactly_what_the_binding_defines():
    """``_core.pyi`` types every name of the binding, every method of ``Core``, and
    nothing else: mypy then refuses a call of a method that does not exist."""
    stub = ast.parse((Path(_core.__file__).parent / "_core.pyi").read_text())
    declared = {node.target.id if isinstance(node, ast.AnnAssign) else node.name
                for node in stub.body
                if isinstance(node, ast.FunctionDef | ast.ClassDef | ast.AnnAssign)}
    declared -= {"RunStatus"}   # the stub's own type of a status dict
    defined = {name for name in vars(_core) if not name.startswith("_")
               and name not in ("np", "os")}
    assert declared == defined
    core = next(node for node in stub.body if isinstance(node, ast.ClassDef)
                and node.name == "Core")
    methods = {node.name for node in core.body if isinstance(node, ast.FunctionDef)}
    assert methods - {"__init__"} == {name for name in dir(_core.Core)
                                      if not name.startswith("_")}
    for enum in ("FmStatus", "FmLawKind"):   # the C header's values, by name
        typed = next(node for node in stub.body if isinstance(node, ast.ClassDef)
                     and node.name == enum)
        values = {node.targets[0].id: node.value.value for node in typed.body
                  if isinstance(node, ast.Assign)}
        assert values == {member.name: int(member) for member in getattr(_core, enum)}


def _imports_the_binding(node) -> bool:
    return isinstance(node, ast.ImportFrom) and (
        (node.module or "").endswith("_core")
        or any(alias.name == "_core" for alias in node.names))


def _calls_the_binding(node) -> bool:
    """A call of a function of the binding (``native.name(...)``) or a use of a
    workspace's core (``._core``)."""
    if isinstance(node, ast.Attribute):
        return node.attr == "_core"
    return (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
            and isinstance(node.func.value, ast.Name) and node.func.value.id == "native")


def test_only_the_workspace_calls_the_core():
    """flexmbd/engine/core.py alone imports the binding, and flexmbd/engine/workspace.py
    alone calls it (the compiler reads its kernel sizes): every call goes through the
    workspace."""
    package = Path(_core.__file__).resolve().parents[1]
    for path in package.rglob("*.py"):
        where = path.relative_to(package).as_posix()
        nodes = list(ast.walk(ast.parse(path.read_text())))
        if any(map(_imports_the_binding, nodes)):
            assert where == "engine/core.py", where
        if any(map(_calls_the_binding, nodes)):
            assert where == "engine/workspace.py", where
