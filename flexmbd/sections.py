"""Cross-sections and materials of beams: the ``ESTIFF`` and ``EM`` values a spatial beam
takes, computed as SPACAR Light computes them.

A :class:`Material` is ``E``, ``G`` and ``rho``. A section is a :class:`Rectangle`
(``w`` along the beam's local y axis, the orientation vector, ``t`` along z), a
:class:`Circle` or a :class:`Tube`. :func:`beam_values` gives, for a section of a
material, the spatial beam's

* stiffness ``EA, GIt, EIy, EIz, sy, sz`` [N, N m^2, m^2] with the shear flexibilities
  ``sy = EIy/(G A k)``, ``sz = EIz/(G A k)`` (Cowper's shear factor ``k``), and the warping
  stiffness ``ECw`` [N m^4];
* mass ``rhoA`` [kg/m] and section inertias per length ``rho(Iy+Iz), rhoIy, rhoIz, rhoIyz``
  [kg m], and the warping inertia ``rhoCw`` [kg m^3],

in the order of a ``.dat`` file's ``ESTIFF`` and ``EM`` lines. For a leaf of 50 x 0.2 mm in
steel (E 210 GPa, G 70 GPa, rho 7800 kg/m^3) they equal, to the last printed digit, the
values SPACAR Light writes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from . import checks
from .errors import ArgumentError

#: SPACAR Light ends the torsion series of a rectangle when a term is below this fraction
#: of the sum (the constant is then at most 4.3e-5 off the converged value)
SERIES_TOLERANCE = 1e-4


@dataclass(frozen=True)
class Material:
    """An isotropic material: Young's modulus ``E`` [Pa], shear modulus ``G`` [Pa] and
    density ``rho`` [kg/m^3] (0 for a massless beam)."""

    E: float
    G: float
    rho: float = 0.0

    def __post_init__(self):
        for name in ("E", "G"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and value == math.inf):  # rigid()
                value = checks.real(value, f"Material {name}")
            if not value > 0.0:
                raise ArgumentError(name, f"must be positive [Pa], got {value:g}")
        if not checks.real(self.rho, "Material rho") >= 0:
            raise ArgumentError("rho", f"must be 0 or more [kg/m^3], got {self.rho:g}")

    @classmethod
    def from_poisson(cls, E: float, nu: float, rho: float = 0.0) -> Material:
        """From ``E`` [Pa] and Poisson's ratio ``nu`` [-]: ``G = E / (2 (1 + nu))``."""
        nu = checks.real(nu, "nu")
        if not -1.0 < nu < 0.5 + 1e-12:
            raise ArgumentError("nu", f"Poisson's ratio must lie in (-1, 0.5], got {nu:g}")
        return cls(E, E / (2.0 * (1.0 + nu)), rho)

    @classmethod
    def rigid(cls, rho: float) -> Material:
        """A rigid body's material of density ``rho`` [kg/m^3]: ``E = G = inf``; a beam of it
        takes only mass and section inertia (:meth:`flexmbd.ModelBuilder.set_section`)."""
        return cls(math.inf, math.inf, rho)

    @property
    def is_rigid(self) -> bool:
        return math.isinf(self.E) or math.isinf(self.G)

    @property
    def nu(self) -> float:
        """Poisson's ratio ``E / (2 G) - 1`` [-], as SPACAR Light takes it."""
        return self.E / (2.0 * self.G) - 1.0

    def doubts(self) -> list[str]:
        """What in the numbers points at another unit or at swapped moduli: a modulus
        softer than any rubber (GPa or MPa given for Pa), a density lighter than any foam
        (g/cm^3 for kg/m^3), a Poisson's ratio no isotropic solid has. Empty when they
        look like a material's."""
        return material_doubts(self.E, self.G, self.rho)


#: below this a modulus [Pa] is softer than any rubber: a number in GPa or MPa, likely
SOFTEST_MODULUS = 1e6
#: below this a density [kg/m^3] is lighter than any foam: g/cm^3, likely
LIGHTEST_DENSITY = 30.0
#: how far outside [0, 0.5] a Poisson's ratio from E and G may lie (rounded moduli)
POISSON_SLACK = 0.02


def material_doubts(E: float | None, G: float | None, rho: float | None,
                    names: tuple[str, str, str] = ("E", "G", "rho")) -> list[str]:
    """:meth:`Material.doubts` of moduli ``E``, ``G`` [Pa] and density ``rho`` [kg/m^3]
    (``None``: not given; infinite: rigid), each message naming its value by ``names``."""
    out = []
    for name, value in zip(names[:2], (E, G), strict=True):
        if value is not None and 0 < value < SOFTEST_MODULUS:
            unit, factor = ("GPa", 1e9) if value < 1e3 else ("MPa (N/mm^2)", 1e6)
            out.append(f"{name} = {value:g} Pa is softer than any rubber: moduli are in Pa "
                       f"({value:g} {unit} is {value * factor:g})")
    if E and G and SOFTEST_MODULUS <= E < math.inf and SOFTEST_MODULUS <= G < math.inf:
        nu = E / (2.0 * G) - 1.0
        if not -POISSON_SLACK <= nu <= 0.5 + POISSON_SLACK:
            out.append(f"{names[0]} / (2 {names[1]}) - 1 = {nu:.3g} is no Poisson's ratio of "
                       f"an isotropic solid (0 to 0.5; steel 0.3): {names[1]} is the shear "
                       f"modulus E / (2 (1 + nu)), {E / 2.6:.3g} Pa for nu = 0.3")
    if rho is not None and 0 < rho < LIGHTEST_DENSITY:
        out.append(f"{names[2]} = {rho:g} kg/m^3 is lighter than any foam: densities are in "
                   f"kg/m^3 ({rho:g} g/cm^3 is {rho * 1e3:g})")
    return out


@dataclass(frozen=True)
class SectionProperties:
    """The constants of a cross-section: area ``A`` [m^2], second moments ``Iy`` (about the
    local y axis), ``Iz``, ``Iyz`` [m^4], torsion constant ``It`` [m^4], warping constant
    ``Cw`` [m^6]."""

    A: float
    Iy: float
    Iz: float
    Iyz: float
    It: float
    Cw: float


#: the section resultants' order: normal force, shear forces, torque, bending moments
RESULTANTS = ("N", "Qy", "Qz", "T", "My", "Mz")


class Section:
    """A cross-section: :meth:`properties`, Cowper's shear factor :meth:`shear_factor`, and
    the largest von Mises stress of its resultants (:meth:`largest_stress`)."""

    def properties(self) -> SectionProperties:
        raise NotImplementedError

    def shear_factor(self, nu: float) -> float:
        raise NotImplementedError

    def stress_points(self, resultants) -> list[tuple[str, float, float]]:
        """``(point, sigma, tau)`` [Pa] at the points where the largest stress can be, for
        the resultants ``(N, Qy, Qz, T, My, Mz)`` [N, N m] in the beam's local axes, and a
        warping beam's bimoment ``B`` [N m^2] after them."""
        raise NotImplementedError

    def largest_stress(self, resultants) -> tuple[float, str]:
        """The largest von Mises stress ``sqrt(sigma^2 + 3 tau^2)`` [Pa] over the section for
        the resultants ``(N, Qy, Qz, T, My, Mz)``, and the point where it is."""
        stress, point = max((math.sqrt(sigma**2 + 3.0 * tau**2), point)
                            for point, sigma, tau in self.stress_points(resultants))
        return stress, point


def _positive(value, name: str) -> float:
    value = checks.real(value, name)
    if not value > 0:
        raise ArgumentError(name, f"must be positive [m], got {value:g}")
    return value


def rectangle_torsion(b: float, c: float, tolerance: float = SERIES_TOLERANCE) -> float:
    """The torsion constant ``It`` [m^4] of a ``b`` x ``c`` rectangle (Timoshenko and Goodier):
    ``(b c^3/3) [1 - (192/pi^5)(c/b) sum_{n odd} tanh(n pi b/(2c))/n^5]`` with ``b >= c``,
    the sum ended when a term falls below ``tolerance`` of it (SPACAR Light's rule by
    default; 0 sums until the terms no longer change it)."""
    b, c = max(b, c), min(b, c)
    stop = max(tolerance, 1e-17)   # 0: until a term no longer changes the sum
    total, n = 0.0, 1
    while True:
        term = math.tanh(n * math.pi * b / (2.0 * c)) / n**5
        total += term
        if term < stop * total:    # SPACAR Light's test, after adding the term
            break
        n += 2
    return b * c**3 / 3.0 * (1.0 - 192.0 / math.pi**5 * (c / b) * total)


@dataclass(frozen=True)
class Rectangle(Section):
    """A ``w`` x ``t`` rectangle [m]: ``w`` along the beam's local y axis (the orientation
    vector), ``t`` along z. A leaf spring is wide in y and thin in z."""

    w: float
    t: float

    def __post_init__(self):
        _positive(self.w, "w")
        _positive(self.t, "t")

    def properties(self) -> SectionProperties:
        w, t = self.w, self.t
        return SectionProperties(A=w * t, Iy=w * t**3 / 12.0, Iz=t * w**3 / 12.0, Iyz=0.0,
                                 It=rectangle_torsion(w, t), Cw=w**3 * t**3 / 144.0)

    def shear_factor(self, nu: float) -> float:
        """Cowper's ``k = 10 (1 + nu) / (12 + 11 nu)``."""
        return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)

    def stress_points(self, resultants) -> list[tuple[str, float, float]]:
        """The four corners (normal stress only), the middles of the long sides and of the
        short sides: bending and normal stress, St Venant torsion (Timoshenko and Goodier's
        series) and the parabolic shear ``1.5 |Q| / A`` along the side."""
        N, Qy, Qz, T, My, Mz = (float(v) for v in resultants[:6])
        bimoment = float(resultants[6]) if len(resultants) > 6 else 0.0
        s = self.properties()
        w, t = self.w, self.t

        def normal(y, z):   # with restrained warping B omega / Cw, omega = y z (FLEXURES 4)
            return N / s.A + My * z / s.Iy - Mz * y / s.Iz + bimoment * y * z / s.Cw

        long_, short = _rectangle_torsion_shear(max(w, t), min(w, t), s.It)
        # the long sides run along the larger dimension: along y when w > t
        wide = w >= t
        tau_long = abs(T) * long_ + 1.5 * abs(Qy if wide else Qz) / s.A
        tau_short = abs(T) * short + 1.5 * abs(Qz if wide else Qy) / s.A
        corners = max((abs(normal(sy * w / 2, sz * t / 2)), f"corner ({sy:+.0f}, {sz:+.0f})")
                      for sy in (-1, 1) for sz in (-1, 1))
        across_t = max(abs(normal(0.0, t / 2)), abs(normal(0.0, -t / 2)))
        across_w = max(abs(normal(w / 2, 0.0)), abs(normal(-w / 2, 0.0)))
        middles_long = across_t if wide else across_w
        middles_short = across_w if wide else across_t
        return [(corners[1], corners[0], 0.0),
                ("middle of a long side", middles_long, tau_long),
                ("middle of a short side", middles_short, tau_short)]


@dataclass(frozen=True)
class Circle(Section):
    """A solid circle of diameter ``d`` [m] (a wire flexure)."""

    d: float

    def __post_init__(self):
        _positive(self.d, "d")

    def properties(self) -> SectionProperties:
        inertia = math.pi * self.d**4 / 64.0
        return SectionProperties(A=math.pi * self.d**2 / 4.0, Iy=inertia, Iz=inertia,
                                 Iyz=0.0, It=2.0 * inertia, Cw=0.0)

    def shear_factor(self, nu: float) -> float:
        """Cowper's ``k = 6 (1 + nu) / (7 + 6 nu)``."""
        return 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)

    def stress_points(self, resultants) -> list[tuple[str, float, float]]:
        """The outer fibre (bending, normal force, torsion) and the neutral axis (shear
        ``4/3 |Q| / A`` added to the torsion)."""
        return _round_stress_points(self.properties(), resultants, self.d / 2, 0.0)


@dataclass(frozen=True)
class Tube(Section):
    """A circular tube of outer diameter ``outer`` and inner diameter ``inner`` [m]."""

    outer: float
    inner: float

    def __post_init__(self):
        _positive(self.outer, "outer")
        inner = checks.real(self.inner, "inner")
        if not 0 <= inner < self.outer:
            raise ArgumentError("inner", f"must lie in [0, outer = {self.outer:g}) [m], got "
                                         f"{inner:g}")

    def properties(self) -> SectionProperties:
        inertia = math.pi * (self.outer**4 - self.inner**4) / 64.0
        return SectionProperties(A=math.pi * (self.outer**2 - self.inner**2) / 4.0, Iy=inertia,
                                 Iz=inertia, Iyz=0.0, It=2.0 * inertia, Cw=0.0)

    def shear_factor(self, nu: float) -> float:
        """Cowper's ``k = 6 (1+nu)(1+m^2)^2 / ((7+6nu)(1+m^2)^2 + (20+12nu) m^2)``,
        ``m = inner/outer``."""
        m2 = (self.inner / self.outer) ** 2
        return 6.0 * (1.0 + nu) * (1.0 + m2) ** 2 / ((7.0 + 6.0 * nu) * (1.0 + m2) ** 2
                                                      + (20.0 + 12.0 * nu) * m2)

    def stress_points(self, resultants) -> list[tuple[str, float, float]]:
        """As the circle's, with the hollow section's largest shear of a force."""
        return _round_stress_points(self.properties(), resultants, self.outer / 2,
                                    self.inner / 2)


def _rectangle_torsion_shear(b: float, c: float, It: float) -> tuple[float, float]:
    """St Venant shear per unit torque [Pa/(N m)] at the middles of the long and of the
    short sides of a ``b >= c`` rectangle of torsion constant ``It``."""
    long_sum = short_sum = 0.0
    for k in range(200):
        n = 2 * k + 1
        ratio = n * math.pi * b / (2.0 * c)
        long_sum += 1.0 / (n**2 * math.cosh(ratio)) if ratio < 700 else 0.0
        short_sum += (-1) ** k * math.tanh(ratio) / n**2
    return (c / It * (1.0 - 8.0 / math.pi**2 * long_sum),
            c / It * 8.0 / math.pi**2 * short_sum)


def _round_stress_points(s: SectionProperties, resultants, outer: float, inner: float
                         ) -> list[tuple[str, float, float]]:
    """The outer fibre and the neutral axis of a circle or tube of radii ``outer``,
    ``inner``."""
    N, Qy, Qz, T, My, Mz = (float(v) for v in resultants[:6])
    moment, force = math.hypot(My, Mz), math.hypot(Qy, Qz)
    torsion = abs(T) * outer / s.It
    shear = 4.0 / 3.0 * (outer**2 + outer * inner + inner**2) / (outer**2 + inner**2)
    return [("outer fibre", abs(N) / s.A + moment * outer / s.Iy, torsion),
            ("neutral axis", abs(N) / s.A, torsion + shear * force / s.A)]


@dataclass(frozen=True)
class BeamValues:
    """The spatial beam's values of a section in a material, in the order of the ``.dat``
    lines: ``estiff`` = ``(EA, GIt, EIy, EIz, sy, sz, ECw)`` and ``em`` = ``(rhoA,
    rho(Iy+Iz), rhoIy, rhoIz, rhoIyz, rhoCw)``."""

    estiff: tuple[float, ...]
    em: tuple[float, ...]

    @property
    def stiffness(self) -> dict[str, float]:
        """The builder's stiffness values by name (without the warping stiffness)."""
        names = ("axial", "torsion", "bending_y", "bending_z", "shear_y", "shear_z")
        return dict(zip(names, self.estiff[:6], strict=True))

    @property
    def mass_per_length(self) -> float:
        return self.em[0]

    @property
    def section_inertia(self) -> tuple[float, float, float, float]:
        """``(Jxx, Jyy, Jzz, Jyz)`` per length [kg m]."""
        return (self.em[1], self.em[2], self.em[3], self.em[4])


def beam_values(section: Section, material: Material) -> BeamValues:
    """The ``ESTIFF`` and ``EM`` values of ``section`` in ``material`` (module docstring)."""
    if not isinstance(section, Section):
        raise ArgumentError("section", f"must be a Rectangle, Circle or Tube, got "
                                       f"{type(section).__name__}")
    if not isinstance(material, Material):
        raise ArgumentError("material", f"must be a Material, got {type(material).__name__}")
    s = section.properties()
    E, G, rho = material.E, material.G, material.rho
    kGA = section.shear_factor(material.nu) * G * s.A
    estiff = (E * s.A, G * s.It, E * s.Iy, E * s.Iz, E * s.Iy / kGA, E * s.Iz / kGA, E * s.Cw)
    em = (rho * s.A, rho * (s.Iy + s.Iz), rho * s.Iy, rho * s.Iz, rho * s.Iyz, rho * s.Cw)
    return BeamValues(estiff, em)
