"""The course exercises (EXERCISES.md) as runnable, tested examples.

Each module builds its model with the public API, prints the values it checks
against closed-form results and can save a plot and a movie. Run them as
``flexmbd example NAME`` or ``python examples/<module>.py``; the test suite
imports them, so they cannot rot.
"""

from pathlib import Path

#: the folder of the example scripts and SPACAR input files (``*.dat``)
EXAMPLES_DIR = Path(__file__).resolve().parent

#: name -> (module, preset arguments, description)
EXAMPLES: dict[str, tuple[str, list[str], str]] = {
    "sliding-truss": (
        "sliding_bar", ["--variant", "truss"],
        "EXERCISES 1a-d: sliding bar as a truss, prescribed end position",
    ),
    "sliding-beam": (
        "sliding_bar", ["--variant", "beam"],
        "EXERCISES 1e-j: sliding bar as a rigid beam, prescribed rotation",
    ),
    "slider-crank-kin": (
        "slider_crank_kinematics", [],
        "EXERCISES 2: slider-crank kinematics, transfer functions and closed-form checks",
    ),
    "slider-crank-dyn": (
        "slider_crank_dynamics", [],
        "EXERCISES 3: rigid slider-crank dynamics, torque, reactions, PD-controlled crank",
    ),
    "slider-crank-flex": (
        "slider_crank_flex", [],
        "EXERCISES 4: slider-crank with a flexible rod of --nbeams beams, v/l2 against crank angle",
    ),
    "slider-crank-modes": (
        "slider_crank_modes", [],
        "EXERCISES 4's rod: eigenfrequencies along a crank revolution, at rest pinned-pinned",
    ),
    "symbolic-course": (
        "symbolic_course", [],
        "EXERCISES 1-4's symbolic steps: ydot_q, F_q(phi2), Mbar lumped = consistent, tau2, "
        "generated flexible slider-crank",
    ),
    "parallel-guide": (
        "parallel_guide", [],
        "a flexure: parallel leaf-spring guide, stiffness, frequencies, buckling, stroke, Bode",
    ),
    "spatial-slider-crank": (
        "spatial_slider_crank", [],
        "a spatial slider-crank: tilted crank axis, offset slider line, spherical rod ends; "
        "kinematics and torque against the closed form",
    ),
    "rotating-beam": (
        "rotating_beam", [],
        "a rotating flexible beam: in-plane and out-of-plane frequencies against the speed "
        "(Southwell), a spin-up under gravity",
    ),
    "cross-spring-pivot": (
        "cross_spring_pivot", [],
        "a spatial flexure: cross-spring pivot, stiffness in all directions, frequencies, "
        "30-degree rotation in load steps",
    ),
    "flexures": (
        "flexures", [],
        "SPACAR Light's examples through flexmbd.light: the cross hinge with warping, a "
        "parallel guide's transfer function, a wire flexure's buckling",
    ),
}
