"""Matrix-of-restitution tables, the exact MoR solver, the eMD* collision rule, and whole
runs of a config with any engine (``emdstar.run``).

The matrix of restitution (MoR) of Müller & Pöschel (2013) maps a collision of two
soft, frictionless spheres to four numbers: eps_r (separation after the collision over
the contact distance), eps_rdot (normal velocity after over before; -eps_n), eps_phi
(rotation of the line of centres, rad) and eps_t (duration over the time scale T).

    import emdstar
    t = emdstar.Table.default("hertz")                # or emdstar.Table.load(path)
    m = t.lookup(young=1e9, poisson=0.3, dissipation=1e-5, radius=0.01,
                 density=2500.0, speed=[0.5, 1.0, 2.0], eccentricity=0.3)
    x = emdstar.mor(model="hertz", young=1e9, poisson=0.3, dissipation=1e-5,
                    radius=0.01, density=2500.0, speed=1.0, eccentricity=0.3)
    print(m["eps_rdot"], x["eps_t"] * x["time_scale"])

Keywords are the command line's flag names: linear ``stiffness`` (N/m) and ``damping``
(kg/s), Hertz ``young`` (Pa), ``poisson`` and ``dissipation`` (A, s); then ``radius``
(m), ``density`` (kg/m^3), ``speed`` (m/s, the relative speed at contact) and
``eccentricity`` (e = d/l, in [0, 1)), and optionally ``radius2``/``density2`` for a
second sphere of another size (``radius2=0`` means a flat wall). Every argument is a
number or an array; arrays broadcast like numpy's. Results are dicts of numpy arrays of
the broadcast shape.

For many impacts of one pair, ``t.pair(young=..., radius=..., ...)`` restricts the table
to that pair once; its ``lookup(speed=..., eccentricity=...)`` is about twice as fast.

Tables are immutable and may be shared between threads.
"""

from __future__ import annotations

import numpy as np

from . import _core

__all__ = ["Table", "PairTable", "mor", "mor_scaled", "collide", "run", "LAW_KEYS"]

#: The law parameters of each model, in order.
LAW_KEYS = {
    "linear": ("stiffness", "damping"),
    "hertz": ("young", "poisson", "dissipation"),
}

_GEOMETRY = ("radius", "density", "speed", "eccentricity")
_COLUMNS = ("one_minus_eps_r", "eps_r", "eps_rdot", "eps_phi", "eps_t", "time_scale", "source")


def _check_keywords(what, want, params):
    """Raises TypeError naming the missing and unknown keywords."""
    missing = [k for k in want if k not in params]
    extra = [k for k in params if k not in want]
    if missing or extra:
        raise TypeError(
            f"{what} takes the keywords {', '.join(want)} (and radius2, density2); "
            f"missing: {missing or 'none'}, unknown: {extra or 'none'}"
        )


def _columns(model, params, radius2, density2):
    """Checks the keywords and broadcasts every input to one shape."""
    if model not in LAW_KEYS:
        raise ValueError(f"unknown model {model!r}: expected 'linear' or 'hertz'")
    want = LAW_KEYS[model] + _GEOMETRY
    _check_keywords(f"the {model} model", want, params)
    radius2 = params["radius"] if radius2 is None else radius2
    density2 = params["density"] if density2 is None else density2
    arrays = [np.asarray(params[k], dtype=np.float64) for k in want]
    arrays += [np.asarray(radius2, dtype=np.float64), np.asarray(density2, dtype=np.float64)]
    shaped = np.broadcast_arrays(*arrays)
    shape = shaped[0].shape
    flat = [np.ascontiguousarray(a.ravel()) for a in shaped]
    nlaw = len(LAW_KEYS[model])
    law, (r, rho, v, e), (r2, rho2) = flat[:nlaw], flat[nlaw : nlaw + 4], flat[nlaw + 4 :]
    return shape, law, (r, rho, r2, rho2, v, e)


def _result(shape, cols, with_source):
    out = {name: c.reshape(shape) for name, c in zip(_COLUMNS, cols)}
    if with_source:
        out["source"] = np.where(out["source"] == 0.0, "table", "exact").reshape(shape)
    else:
        del out["source"]
    return out


class Table:
    """A matrix-of-restitution table: ``Table.default(model)`` or ``Table.load(path)``."""

    def __init__(self, core):
        self._t = core

    @classmethod
    def default(cls, model: str) -> "Table":
        """The default table of ``"linear"`` or ``"hertz"`` (embedded, parsed once)."""
        return cls(_core.Table.default(model))

    @classmethod
    def load(cls, path) -> "Table":
        """A table file, as ``emdstar table build SPEC`` writes them."""
        return cls(_core.Table.load(str(path)))

    @property
    def model(self) -> str:
        """``"linear"`` or ``"hertz"``."""
        return self._t.model

    @property
    def parameter_box(self) -> dict:
        """The physical box the table covers: ``{name: (min, max)}`` in SI units."""
        return dict(self._t.parameter_box)

    @property
    def tolerance(self) -> float:
        """The generator's error goal per component (relative)."""
        return self._t.tolerance

    @property
    def estimated_error(self) -> dict:
        """The largest error estimate of the table's patches, per component."""
        names = ("one_minus_eps_r", "eps_rdot", "eps_phi", "eps_t")
        return dict(zip(names, self._t.estimated_error))

    @property
    def rect(self):
        """[min, max] of the rectangular coordinates a, b, c."""
        return self._t.rect

    def lookup(self, *, exact_fallback: bool = False, radius2=None, density2=None, **params):
        """MoR arrays of impacts from the table.

        Impacts outside the table's box raise ``ValueError`` unless ``exact_fallback``
        is true; then they are solved exactly and ``result["source"]`` says which.
        Returns a dict of arrays: one_minus_eps_r, eps_r, eps_rdot, eps_phi, eps_t,
        time_scale (T, s: the contact lasts eps_t * T) and, with the fallback, source.
        """
        shape, law, geometry = _columns(self.model, params, radius2, density2)
        cols = self._t.lookup(law, list(geometry), bool(exact_fallback))
        return _result(shape, cols, exact_fallback)

    def pair(self, *, radius2=None, density2=None, **params) -> "PairTable":
        """This table restricted to the impacts of one pair: the law's parameters and
        ``radius``, ``density`` (``radius2``, ``density2``) as numbers, no ``speed`` or
        ``eccentricity``. Built once (about a millisecond), its lookups take about half
        the time of ``Table.lookup`` and agree with it to rounding (well within the
        table's accuracy)."""
        want = LAW_KEYS[self.model] + ("radius", "density")
        _check_keywords(f"a {self.model} pair (numbers)", want, params)
        radius2 = params["radius"] if radius2 is None else radius2
        density2 = params["density"] if density2 is None else density2
        law = [float(params[k]) for k in LAW_KEYS[self.model]]
        geometry = [float(params["radius"]), float(params["density"]), float(radius2), float(density2)]
        return PairTable(self._t.pair(law, geometry))

    def __repr__(self):
        return f"emdstar.Table(model={self.model!r}, tolerance={self.tolerance:g})"


class PairTable:
    """A table restricted to one pair's impacts (``Table.pair``); immutable, shareable
    between threads."""

    def __init__(self, core):
        self._p = core

    @property
    def patches(self) -> int:
        """Two-dimensional patches of the restriction (0: lookups go through the full
        table, e.g. for a pair without dissipation)."""
        return self._p.patches

    @property
    def nbytes(self) -> int:
        """Bytes the restriction holds."""
        return self._p.nbytes

    def lookup(self, *, speed, eccentricity, exact_fallback: bool = False):
        """MoR arrays of the pair's impacts (``speed``, ``eccentricity``: numbers or
        arrays, broadcast); the same columns and errors as ``Table.lookup``."""
        v, e = np.broadcast_arrays(np.asarray(speed, dtype=np.float64),
                                   np.asarray(eccentricity, dtype=np.float64))
        shape = v.shape
        cols = self._p.lookup(np.ascontiguousarray(v.ravel()), np.ascontiguousarray(e.ravel()),
                              bool(exact_fallback))
        return _result(shape, cols, exact_fallback)

    def __repr__(self):
        return f"emdstar.PairTable(patches={self.patches})"


def mor(*, model: str, radius2=None, density2=None, **params):
    """Exact MoR arrays (one ODE solve per impact); same keywords as ``Table.lookup``."""
    shape, law, geometry = _columns(model, params, radius2, density2)
    return _result(shape, _core.exact(model, law, list(geometry)), False)


def mor_scaled(*, model: str, l_tilde, c_phi, c_dis):
    """Exact MoR arrays at the scaled parameters (l~, c_phi, c_dis) of Eqs. (42)/(54)."""
    arrays = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in (l_tilde, c_phi, c_dis)))
    shape = arrays[0].shape
    flat = [np.ascontiguousarray(a.ravel()) for a in arrays]
    out = _result(shape, _core.exact_scaled(model, *flat), False)
    del out["time_scale"]
    return out


def collide(*, x1, v1, x2, v2, model: str, table: "Table | None" = None,
            exact_fallback: bool = False, radius2=None, density2=None, **params):
    """The eMD* collision rule (Müller & Pöschel 2013, Sec. IV) in the laboratory frame.

    ``x1, v1, x2, v2`` are positions (m) and velocities (m/s) of the two spheres at
    first touch, arrays of shape (..., 3); the law and sphere keywords are those of
    ``Table.lookup`` without ``speed`` and ``eccentricity`` (they follow from the
    states). With a ``table`` the MoR is looked up (``exact_fallback`` as there), else
    solved exactly. Returns a dict: x1, v1, x2, v2 after the collision, rotated_x1,
    rotated_x2 (the E^phi event), transient_velocity (between E^phi and E^v),
    duration (s), and the MoR columns.
    """
    x1, v1, x2, v2 = (np.asarray(a, dtype=np.float64) for a in (x1, v1, x2, v2))
    shape = np.broadcast_shapes(x1.shape, v1.shape, x2.shape, v2.shape)
    if len(shape) == 0 or shape[-1] != 3:
        raise ValueError(f"positions and velocities must have shape (..., 3), got {shape}")
    x1, v1, x2, v2 = (np.broadcast_to(a, shape).reshape(-1, 3) for a in (x1, v1, x2, v2))
    r, v = x1 - x2, v1 - v2
    dist = np.linalg.norm(r, axis=1)
    vn = -np.einsum("ij,ij->i", r, v) / dist
    speed = np.linalg.norm(v, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        ecc = np.sqrt(np.clip(1.0 - (vn / speed) ** 2, 0.0, None))
    if np.any(~(vn > 0.0)):
        raise ValueError("every pair must approach at contact (normal speed > 0)")
    p = dict(params)
    for k in ("speed", "eccentricity"):
        if k in p:
            raise TypeError(f"collide takes no {k!r}: it follows from x and v")
    n = r.shape[0]
    p["speed"], p["eccentricity"] = speed, ecc
    for k in ("radius", "density"):
        if k in p:
            p[k] = np.broadcast_to(np.asarray(p[k], dtype=np.float64), shape[:-1]).reshape(n)
    r2 = p.get("radius") if radius2 is None else np.broadcast_to(radius2, shape[:-1]).reshape(n)
    rho2 = p.get("density") if density2 is None else np.broadcast_to(density2, shape[:-1]).reshape(n)
    if table is not None:
        if table.model != model:
            raise ValueError(f"the table is for the {table.model} model, not {model}")
        m = table.lookup(exact_fallback=exact_fallback, radius2=r2, density2=rho2, **p)
    else:
        m = mor(model=model, radius2=r2, density2=rho2, **p)
    radius = np.broadcast_to(np.asarray(p["radius"], dtype=np.float64), (n,))
    density = np.broadcast_to(np.asarray(p["density"], dtype=np.float64), (n,))
    r2 = np.broadcast_to(np.asarray(r2, dtype=np.float64), (n,))
    rho2 = np.broadcast_to(np.asarray(rho2, dtype=np.float64), (n,))
    m1 = 4.0 / 3.0 * np.pi * radius**3 * density
    m2 = 4.0 / 3.0 * np.pi * r2**3 * rho2
    contact = radius + r2
    cols = [np.ascontiguousarray(np.broadcast_to(m[k], (n,)), dtype=np.float64)
            for k in ("one_minus_eps_r", "eps_r", "eps_rdot", "eps_phi", "eps_t")]
    flat = [np.ascontiguousarray(a.ravel()) for a in (x1, v1, x2, v2)]
    out = _core.resolve_collisions(
        *flat, np.ascontiguousarray(m1), np.ascontiguousarray(m2), np.ascontiguousarray(contact),
        cols, np.ascontiguousarray(m["time_scale"].ravel()),
    )
    names = ("x1", "v1", "x2", "v2", "rotated_x1", "rotated_x2", "transient_velocity")
    result = {k: a.reshape(shape) for k, a in zip(names, out[:7])}
    result["duration"] = out[7].reshape(shape[:-1])
    for k, val in m.items():
        result[k] = np.reshape(val, shape[:-1])
    return result


def run(path=None, *, toml: "str | None" = None, engine: str = "md", t_end=None,
        frames: int = 11, mor: str = "table-or-exact"):
    """Runs a config with any engine and samples it at ``frames`` evenly spaced times.

    ``path`` is a config file (TOML, the keys of ``docs/config.md``), or ``toml`` its
    text. ``engine`` is ``"md"``, ``"emd"``, ``"emdstar"`` or ``"hybrid"``; ``t_end``
    (s) overrides the config's; ``mor`` is eMD*'s source of the matrix of restitution
    (``"table-or-exact"``: the default table, exact solves outside it, counted;
    ``"table"``; ``"exact"``). The engines take their defaults as ``emdstar run``
    does (MD: 1/50 of the shortest contact time per step).

    Returns a dict: ``t`` (frames,; the engine's time at each sample: MD stops at the
    step nearest it), ``id``, ``radius``, ``mass`` (n,), ``position``
    and ``velocity`` (frames, n, 3; a particle inside an eMD* collision shows the
    velocity it leaves with), the thermo log ``kinetic_energy``,
    ``potential_energy``, ``granular_temperature``, ``contacts`` (frames,) and
    ``momentum`` (frames, 3), the ``engine`` and its ``mor_fallbacks``. Bad configs
    and options raise ``ValueError`` saying what is wrong.
    """
    if (path is None) == (toml is None):
        raise TypeError("run takes a config file path or toml=<config text>, not both or neither")
    if toml is None:
        with open(path, encoding="utf-8") as f:
            toml = f.read()
    out = _core.run_config(toml, engine, None if t_end is None else float(t_end),
                           int(frames), mor)
    f, n = len(out["t"]), len(out["id"])
    out["position"] = out["position"].reshape(f, n, 3)
    out["velocity"] = out["velocity"].reshape(f, n, 3)
    out["momentum"] = out["momentum"].reshape(f, 3)
    return out
