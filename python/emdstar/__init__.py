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

import json
import os
import sys

import numpy as np

from . import _core

__version__ = _core.__version__

__all__ = ["Table", "PairTable", "mor", "mor_scaled", "collide", "run", "LAW_KEYS", "__version__"]

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


def _model(model):
    """The model's name in lower case, checked."""
    name = str(model).lower()
    if name not in LAW_KEYS:
        raise ValueError(f"unknown force model {model!r}: expected 'linear' or 'hertz' (any case)")
    return name


def _with_restitution(model, params, radius2, density2):
    """``params`` with ``restitution`` (and ``restitution_speed``) replaced by the
    dissipation (``damping`` or ``dissipation``) that gives central impacts of each pair
    that normal restitution, at ``restitution_speed`` (default: each impact's speed;
    the linear dashpot's restitution does not depend on it)."""
    if "restitution" not in params:
        if "restitution_speed" in params:
            raise TypeError("restitution_speed goes with restitution")
        return params
    p = dict(params)
    e = p.pop("restitution")
    speed = p.pop("restitution_speed", p.get("speed", 1.0))
    key = LAW_KEYS[model][-1]
    if key in p:
        raise TypeError(f"give {key} or restitution, not both")
    elastic = LAW_KEYS[model][:-1]
    missing = [k for k in elastic + ("radius", "density") if k not in p]
    if missing:
        raise TypeError(f"restitution needs {', '.join(missing)}")
    r2 = p["radius"] if radius2 is None else radius2
    rho2 = p["density"] if density2 is None else density2
    arrays = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in
                                   [p[k] for k in elastic] + [p["radius"], p["density"], r2, rho2, e, speed]))
    shape = arrays[0].shape
    flat = [np.ascontiguousarray(a.ravel()) for a in arrays]
    k = len(elastic)
    d = _core.dissipation_for_restitution(model, flat[:k], flat[k:k + 4], flat[k + 4], flat[k + 5])
    p[key] = d.reshape(shape)
    return p


def _columns(model, params, radius2, density2):
    """Checks the keywords and broadcasts every input to one shape."""
    model = _model(model)
    params = _with_restitution(model, params, radius2, density2)
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
    """Columns of ``shape``; scalars in give scalars out (``float``, ``str``)."""
    out = {name: c.reshape(shape) for name, c in zip(_COLUMNS, cols)}
    if with_source:
        out["source"] = np.where(out["source"] == 0.0, "table", "exact").reshape(shape)
    else:
        del out["source"]
    if shape == ():
        out = {k: v.item() for k, v in out.items()}
    return out


class Table:
    """A matrix-of-restitution table: ``Table.default(model)`` or ``Table.load(path)``."""

    def __init__(self, core):
        self._t = core

    @classmethod
    def default(cls, model: str) -> "Table":
        """The default table of ``"linear"`` or ``"hertz"`` (embedded, parsed once)."""
        return cls(_core.Table.default(_model(model)))

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

        ``restitution`` (with ``restitution_speed`` for Hertz; default each impact's
        speed) may replace the law's dissipation: the one giving central impacts of the
        pair that normal restitution. Numbers in give numbers out. Impacts outside the table's box raise ``ValueError`` unless ``exact_fallback``
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
    """Exact MoR arrays (one ODE solve per impact); same keywords as ``Table.lookup``
    (``restitution=`` included); numbers in give numbers out."""
    shape, law, geometry = _columns(model, params, radius2, density2)
    return _result(shape, _core.exact(_model(model), law, list(geometry)), False)


def mor_scaled(*, model: str, l_tilde, c_phi, c_dis):
    """Exact MoR arrays at the scaled parameters (l~, c_phi, c_dis) of Eqs. (42)/(54)."""
    arrays = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in (l_tilde, c_phi, c_dis)))
    shape = arrays[0].shape
    flat = [np.ascontiguousarray(a.ravel()) for a in arrays]
    out = _result(shape, _core.exact_scaled(_model(model), *flat), False)
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
    model = _model(model)
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


def _progress_bar():
    """A progress bar on stderr: the fraction of the run done and the time elapsed."""
    import time

    started = time.monotonic()

    def show(fraction):
        width = 40
        done = int(width * min(max(fraction, 0.0), 1.0))
        elapsed = time.monotonic() - started
        sys.stderr.write(f"\r[{'#' * done}{'.' * (width - done)}] {100 * fraction:5.1f} % {elapsed:6.1f} s")
        if fraction >= 1.0:
            sys.stderr.write("\n")
        sys.stderr.flush()

    return show


def _path(p):
    return None if p is None else os.fspath(p)


def run(config=None, *, engine: str = "md", t_end=None, dt=None, threads=None, skin=None,
        mor: str = "table-or-exact", checkpoint=None, resume=None, trajectory=None, log=None,
        frames: int = 11, progress: bool = True, toml: "str | None" = None):
    """Runs a config with any engine, through the run loop of ``emdstar run``.

    ``config`` is a config file path (``str`` or ``Path``; ``initial.file`` is read
    relative to its directory), TOML text, or a ``dict`` of the TOML's keys
    (``docs/config.md``); ``toml=`` also takes the text. ``engine`` is ``"md"``,
    ``"emd"``, ``"emdstar"`` or ``"hybrid"`` (any case); ``t_end`` (s) stops the run there
    instead of at the config's ``t_end`` (which still sets the default step and output
    intervals, as ``emdstar run --t-end`` does); ``dt`` (s) and ``skin`` (m) set MD's and the hybrid's step and Verlet
    skin (default as ``emdstar run``: 1/50 of the shortest contact time); ``threads``
    the worker threads (default all cores; results do not depend on it); ``mor`` eMD*'s
    source of the matrix of restitution (``"table-or-exact"``, ``"table"``,
    ``"exact"``). ``trajectory`` (XYZ, or GSD for ``.gsd``) and ``log`` write files as
    ``emdstar run`` does (none by default); ``checkpoint`` writes the state at the end
    (and at ``[output] restart_interval``); ``resume`` continues from a checkpoint,
    appending to the trajectory and log. A progress bar goes to stderr unless
    ``progress=False``. Ctrl-C stops the run at its next event or step and raises
    ``KeyboardInterrupt``, the state saved in ``checkpoint`` if one was named.

    Returns a dict: ``t`` (frames,), the engine's times of ``frames`` evenly spaced
    samples; ``position``, ``velocity``, ``angular_velocity`` (frames, n, 3) and
    ``image`` (frames, n, 3: periodic image flags, unwrapped = position + image × box
    size) in config order; ``id``, ``species``, ``material`` (n,; numbers into
    ``materials``, their names), ``radius``, ``mass``; ``log``, the thermo log as named
    columns (``t``, ``step``, ``kinetic_energy``, ``potential_energy``,
    ``total_energy``, ``granular_temperature``, ``px``, ``py``, ``pz``, ``contacts``,
    ``rotational_energy``, ``rotational_temperature``) at the log interval; and
    ``summary``, the run's counters (wall time, steps or events, collisions, MoR
    fallbacks, …). Bad configs and options raise ``ValueError`` saying what is wrong.
    """
    if (config is None) == (toml is None):
        raise TypeError("run takes a config (path, TOML text or dict) or toml=<text>, not both or neither")
    path = text = as_json = None
    if toml is not None:
        text = toml
    elif isinstance(config, dict):
        as_json = json.dumps(config)
    elif isinstance(config, os.PathLike):
        path = os.fspath(config)
    elif isinstance(config, str):
        if "\n" in config or "=" in config:
            text = config
        else:
            path = config
    else:
        raise TypeError(f"config must be a path, TOML text or a dict, not {type(config).__name__}")
    out = _core.run_config(
        path, text, as_json, str(engine), None if t_end is None else float(t_end),
        None if dt is None else float(dt), None if threads is None else int(threads),
        None if skin is None else float(skin), str(mor), _path(checkpoint), _path(resume),
        _path(trajectory), _path(log), int(frames), _progress_bar() if progress else None,
    )
    f, n = len(out["t"]), out.pop("n")
    for k in ("position", "velocity", "angular_velocity", "image"):
        out[k] = out[k].reshape(f, n, 3)
    out["summary"] = json.loads(out.pop("summary_json"))
    return out
