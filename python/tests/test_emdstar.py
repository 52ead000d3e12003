"""The Python interface against independent references: the exact solver, the
analytic central impacts of Schwager & Poschel (2007), and conservation laws."""

import math

import numpy as np
import pytest

import emdstar

LINEAR = dict(stiffness=1e5, damping=0.1, radius=0.005, density=2500.0)
HERTZ = dict(young=1e9, poisson=0.3, dissipation=1e-5, radius=0.01, density=2500.0)


def test_table_lookups_match_exact_solves():
    for model, law in (("linear", LINEAR), ("hertz", HERTZ)):
        t = emdstar.Table.default(model)
        speed = np.array([0.2, 0.7, 2.0])
        ecc = np.array([[0.05], [0.4], [0.8]])
        got = t.lookup(speed=speed, eccentricity=ecc, **law)
        want = emdstar.mor(model=model, speed=speed, eccentricity=ecc, **law)
        assert got["eps_t"].shape == (3, 3)
        for k in ("one_minus_eps_r", "eps_rdot", "eps_phi", "eps_t"):
            rel = np.abs(got[k] / want[k] - 1.0)
            assert rel.max() < 2e-6, (model, k, rel.max())
        np.testing.assert_allclose(got["time_scale"], want["time_scale"], rtol=1e-12)


def test_pair_tables_match_exact_solves_and_the_full_table():
    for model, law in (("linear", LINEAR), ("hertz", HERTZ)):
        t = emdstar.Table.default(model)
        p = t.pair(**law)
        assert p.patches > 0 and p.nbytes > 0
        speed = np.geomspace(0.05, 5.0, 7)[:, None]
        ecc = np.array([0.05, 0.3, 0.6, 0.9])
        got = p.lookup(speed=speed, eccentricity=ecc)
        want = emdstar.mor(model=model, speed=speed, eccentricity=ecc, **law)
        full = t.lookup(speed=speed, eccentricity=ecc, **law)
        assert got["eps_t"].shape == (7, 4)
        for k in ("one_minus_eps_r", "eps_rdot", "eps_phi", "eps_t"):
            assert np.abs(got[k] / want[k] - 1.0).max() < 2e-6, (model, k)
            assert np.abs(np.log(got[k] / full[k])).max() < 1e-7, (model, k)
        np.testing.assert_array_equal(got["time_scale"], full["time_scale"])
    t = emdstar.Table.default("linear")
    p = t.pair(**LINEAR)
    with pytest.raises(ValueError, match="outside the table's box"):
        p.lookup(speed=1e-5, eccentricity=0.1)
    assert p.lookup(speed=1e-5, eccentricity=0.1, exact_fallback=True)["source"] == "exact"
    with pytest.raises(TypeError, match="missing"):
        t.pair(stiffness=1e5, radius=0.005, density=2500.0)


def test_linear_central_impact_is_the_analytic_one():
    # Schwager & Poschel 2007: under-damped dashpot, the collision ends where the force
    # vanishes; eps_n = exp(-beta tau) with tau = (pi - atan(2 beta w / (w^2 - beta^2))) / w.
    k, gamma, r, rho = 1e5, 0.5, 0.005, 2500.0
    m_eff = 0.5 * 4.0 / 3.0 * math.pi * r**3 * rho
    w0 = math.sqrt(k / m_eff)
    beta = gamma / (2 * m_eff)
    w = math.sqrt(w0**2 - beta**2)
    tau = (math.pi - math.atan2(2 * beta * w, w * w - beta * beta)) / w
    x = emdstar.mor(model="linear", stiffness=k, damping=gamma, radius=r, density=rho,
                    speed=1.0, eccentricity=0.0)
    assert abs(-x["eps_rdot"] - math.exp(-beta * tau)) < 1e-9
    assert abs(x["eps_t"] * x["time_scale"] - tau) < 1e-9 * tau
    assert x["eps_phi"] == 0.0


def test_elastic_hertz_impact_lasts_the_scaled_duration():
    # An elastic central Hertz impact lasts 3.218065 time scales and restores the speed.
    x = emdstar.mor(model="hertz", young=1e9, poisson=0.3, dissipation=0.0, radius=0.01,
                    density=2500.0, speed=1.0, eccentricity=0.0)
    assert abs(x["eps_t"] - 3.218065) < 1e-6
    assert abs(x["eps_rdot"] + 1.0) < 1e-9


def test_out_of_box_raises_unless_the_fallback_is_asked_for():
    t = emdstar.Table.default("linear")
    slow = dict(LINEAR, speed=1e-5, eccentricity=0.1)
    with pytest.raises(ValueError, match="outside the table's box"):
        t.lookup(**slow)
    got = t.lookup(exact_fallback=True, **slow)
    assert got["source"] == "exact"
    want = emdstar.mor(model="linear", **slow)
    assert got["eps_t"] == want["eps_t"]
    inside = t.lookup(exact_fallback=True, **dict(LINEAR, speed=1.0, eccentricity=0.1))
    assert inside["source"] == "table"


def test_bad_keywords_and_files_say_what_is_wrong():
    t = emdstar.Table.default("hertz")
    with pytest.raises(TypeError, match="takes the keywords young, poisson"):
        t.lookup(stiffness=1.0, radius=0.01, density=1.0, speed=1.0, eccentricity=0.1)
    with pytest.raises(ValueError, match="poisson"):
        t.lookup(**dict(HERTZ, poisson=0.7), speed=1.0, eccentricity=0.1)
    with pytest.raises(OSError):
        emdstar.Table.load("/nonexistent/table.npz")
    with pytest.raises(ValueError, match="unknown force model"):
        emdstar.Table.default("rigid")


def test_metadata():
    t = emdstar.Table.default("hertz")
    assert t.model == "hertz"
    assert t.parameter_box["young"] == (1e7, 1e11)
    assert 0 < t.tolerance < 1e-5
    assert all(0 < e < 1e-5 for e in t.estimated_error.values())


def test_collisions_conserve_momentum_and_elastic_energy():
    r, rho = 0.01, 2500.0
    m = 4.0 / 3.0 * math.pi * r**3 * rho
    rng = np.random.default_rng(3)
    n = 50
    normal = rng.normal(size=(n, 3))
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    x1 = rng.normal(size=(n, 3))
    x2 = x1 - 2 * r * normal
    vrel = -normal * rng.uniform(0.2, 2.0, size=(n, 1)) + rng.normal(scale=0.5, size=(n, 3)) * 0.3
    v1, v2 = 0.5 * vrel, -0.5 * vrel
    law = dict(young=1e9, poisson=0.3, dissipation=0.0, radius=r, density=rho)
    for table in (None, emdstar.Table.default("hertz")):
        out = emdstar.collide(x1=x1, v1=v1, x2=x2, v2=v2, model="hertz", table=table,
                              exact_fallback=True, **law)
        p_before = m * (v1 + v2)
        p_after = m * (out["v1"] + out["v2"])
        np.testing.assert_allclose(p_after, p_before, atol=1e-14)
        e_before = 0.5 * m * (np.sum(v1**2, axis=1) + np.sum(v2**2, axis=1))
        e_after = 0.5 * m * (np.sum(out["v1"] ** 2, axis=1) + np.sum(out["v2"] ** 2, axis=1))
        np.testing.assert_allclose(e_after, e_before, rtol=1e-6)
        assert np.all(out["duration"] > 0)


# A head-on elastic collision of two equal linear-spring spheres (R = 0.1 m, 1140 kg/m³,
# k = 2000 N/m, 1 m/s each): they touch at 0.4 s, stay in contact for
# tau = pi*sqrt(m_eff/k), leave with swapped velocities from where they touched.
HEAD_ON = """
t_end = 1.0
[material]
model = "linear"
stiffness = 2000.0
damping = 0.0
density = 1140.0
[[particles]]
radius = 0.1
position = [-0.5, 0.0, 0.0]
velocity = [1.0, 0.0, 0.0]
[[particles]]
radius = 0.1
position = [0.5, 0.0, 0.0]
velocity = [-1.0, 0.0, 0.0]
"""


def _head_on_final_x1():
    m = 1140.0 * 4.0 / 3.0 * math.pi * 0.1**3
    tau = math.pi * math.sqrt(0.5 * m / 2000.0)
    return -0.1 - (1.0 - 0.4 - tau), tau


@pytest.mark.parametrize("engine,tol", [("md", 1e-3), ("emdstar", 1e-6), ("hybrid", 1e-3)])
def test_runs_of_a_head_on_collision_end_where_newton_says(engine, tol):
    out = emdstar.run(toml=HEAD_ON, engine=engine, frames=5)
    x1, _ = _head_on_final_x1()
    assert out["engine"] == engine
    assert out["position"].shape == (5, 2, 3) and out["t"][-1] == pytest.approx(1.0)
    assert abs(out["position"][-1, 0, 0] - x1) < tol * 0.2
    assert np.allclose(out["velocity"][-1], [[-1.0, 0, 0], [1.0, 0, 0]], atol=tol)
    log = out["log"]
    assert max(np.abs(log[k]).max() for k in ("px", "py", "pz")) < 1e-12
    assert log["kinetic_energy"][-1] == pytest.approx(log["kinetic_energy"][0], rel=tol)


def test_classic_emd_misses_the_contact_duration():
    out = emdstar.run(toml=HEAD_ON, engine="emd", frames=2)
    x1, tau = _head_on_final_x1()
    # An instantaneous collision leaves tau too early: v*tau behind the soft spheres.
    assert out["position"][-1, 0, 0] - x1 == pytest.approx(-tau, rel=1e-6)


def test_run_reads_files_and_refuses_bad_input(tmp_path):
    path = tmp_path / "head_on.toml"
    path.write_text(HEAD_ON)
    out = emdstar.run(path, engine="md", t_end=0.2, frames=3)
    # Samples fall on the engine's own steps (MD's step is set by the config's t_end):
    # MD takes the step nearest each time.
    assert out["t"][0] == 0.0 and abs(out["t"][-1] - 0.2) < 0.001
    assert abs(out["t"][1] - 0.1) < 0.01
    with pytest.raises(ValueError, match="the engines are"):
        emdstar.run(path, engine="lammps")
    with pytest.raises(ValueError, match="t_end"):
        emdstar.run(path, t_end=-1.0)
    with pytest.raises(ValueError, match="config"):
        emdstar.run(toml=HEAD_ON.replace("stiffness = 2000.0", "stiffness = -1.0"))
    with pytest.raises(TypeError):
        emdstar.run()


def test_collide_refuses_pairs_not_in_contact():
    # Touching (|x1 - x2| = 2R) passes; 0.5 m apart with R = 0.01 m, or overlapping,
    # is refused: the rule would move them to where they never were.
    law = dict(young=1e9, poisson=0.3, dissipation=0.0, radius=0.01, density=2500.0)
    v1, v2 = [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    out = emdstar.collide(x1=[0, 0, 0], v1=v1, x2=[0.02, 0, 0], v2=v2, model="hertz", **law)
    assert out["v2"][0] > 0.0
    for x2 in ([0.5, 0, 0], [0.019, 0, 0]):
        with pytest.raises(ValueError, match="not in contact"):
            emdstar.collide(x1=[0, 0, 0], v1=v1, x2=x2, v2=v2, model="hertz", **law)


# A gas whose run takes minutes, sampled once at its end: only a stop request seen at
# each step or event ends it early.
LONG_GAS = """
t_end = 1e6
[material]
model = "hertz"
young = 1e9
poisson = 0.4
dissipation = 0.0
density = 1140.0
[gas]
count = 500
radius = 0.1
arrangement = "random"
packing_fraction = 0.2
rms_speed = 1.0
seed = 42
"""


@pytest.mark.parametrize("engine", ["md", "emd", "emdstar", "hybrid"])
def test_run_raises_keyboard_interrupt_within_a_second_of_ctrl_c(engine):
    import signal
    import subprocess
    import sys
    import time

    script = (
        "import sys, time, emdstar\n"
        "print('started', flush=True)\n"
        "try:\n"
        "    emdstar.run(toml=sys.argv[1], engine=sys.argv[2], frames=2)\n"
        "    print('finished', flush=True)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', time.time(), flush=True)\n"
    )
    child = subprocess.Popen([sys.executable, "-c", script, LONG_GAS, engine],
                             stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "started"
    time.sleep(3.0)  # set-up done, the run under way
    sent = time.time()
    child.send_signal(signal.SIGINT)
    try:
        out, _ = child.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        child.kill()
        child.communicate()
        raise
    words = out.split()
    assert words[0] == "interrupted", out
    took = float(words[1]) - sent
    print(f"{engine}: KeyboardInterrupt {1e3 * took:.1f} ms after Ctrl-C")
    assert took < 1.0, f"{engine}: KeyboardInterrupt {took:.2f} s after Ctrl-C"


GAS = {
    "t_end": 0.2,
    "material": {"model": "hertz", "young": 1e7, "poisson": 0.3, "restitution": 0.8,
                 "restitution_speed": 1.0, "density": 1000.0, "friction": 0.3,
                 "tangential_stiffness": 1e4},
    "gas": {"count": 64, "radius": 0.05, "arrangement": "lattice",
            "packing_fraction": 0.05, "rms_speed": 2.0, "seed": 1},
}


def test_run_takes_the_cli_options_and_returns_the_whole_state(tmp_path, capsys):
    out = emdstar.run(GAS, engine="MD", dt=1e-4, threads=1, skin=0.02, frames=5,
                      trajectory=tmp_path / "gas.gsd", log=tmp_path / "gas.log",
                      checkpoint=tmp_path / "gas.ckpt")
    assert "%" in capsys.readouterr().err  # the progress bar
    assert out["engine"] == "md" and out["position"].shape == (5, 64, 3)
    assert out["angular_velocity"].shape == (5, 64, 3) and out["image"].dtype == np.int32
    assert out["materials"] == ["material"] and set(out["material"]) == {0}
    assert out["summary"]["dt"] == pytest.approx(1e-4) and out["summary"]["steps"] == 2000
    assert out["summary"]["skin"] == 0.02
    # The log in memory is the log file, column by column.
    text = np.loadtxt(tmp_path / "gas.log")
    log = out["log"]
    assert text.shape[0] == len(log["t"]) and np.allclose(text[:, 5], log["granular_temperature"])
    assert np.allclose(text[:, 11], log["rotational_temperature"]) and log["rotational_temperature"][-1] > 0
    assert (tmp_path / "gas.gsd").stat().st_size > 0 and (tmp_path / "gas.ckpt").exists()
    # Resumed from the checkpoint at t = 0.2 up to 0.3: the same config as a dict.
    more = emdstar.run(GAS, engine="md", dt=1e-4, skin=0.02, t_end=0.3, frames=3,
                       resume=tmp_path / "gas.ckpt", log=tmp_path / "gas.log", progress=False)
    assert more["summary"]["resumed_from"] == pytest.approx(0.2)
    assert more["t"][0] == pytest.approx(0.2) and more["t"][-1] == pytest.approx(0.3)
    assert np.allclose(more["position"][0], out["position"][-1])
    # TOML text and a path give the same run as the dict.
    (tmp_path / "gas.toml").write_text(
        "t_end = 0.2\n[material]\nmodel = \"hertz\"\nyoung = 1e7\npoisson = 0.3\nrestitution = 0.8\n"
        "restitution_speed = 1.0\ndensity = 1000.0\nfriction = 0.3\ntangential_stiffness = 1e4\n"
        "[gas]\ncount = 64\nradius = 0.05\narrangement = \"lattice\"\npacking_fraction = 0.05\n"
        "rms_speed = 2.0\nseed = 1\n")
    again = emdstar.run(tmp_path / "gas.toml", engine="md", dt=1e-4, skin=0.02, frames=5, progress=False)
    assert np.array_equal(again["position"], out["position"])
    with pytest.raises(ValueError, match="gas.count"):
        emdstar.run({**GAS, "gas": {**GAS["gas"], "count": -1}}, progress=False)


def test_scalars_in_give_scalars_out_and_restitution_sets_the_dissipation():
    law = dict(young=1e9, poisson=0.3, radius=0.01, density=2500.0, speed=1.0, eccentricity=0.0)
    out = emdstar.mor(model="Hertz", restitution=0.7, **law)
    assert isinstance(out["eps_r"], float)
    # A central impact at the speed it was matched at has that restitution.
    assert -out["eps_rdot"] == pytest.approx(0.7, abs=1e-8)
    t = emdstar.Table.default("HERTZ").lookup(restitution=0.7, **law)
    assert isinstance(t["eps_rdot"], float) and -t["eps_rdot"] == pytest.approx(0.7, abs=1e-3)
    arrays = emdstar.mor(model="linear", stiffness=1e4, restitution=[0.5, 0.9], radius=0.01,
                         density=2500.0, speed=1.0, eccentricity=0.0)
    assert np.allclose(-arrays["eps_rdot"], [0.5, 0.9], atol=1e-8)
    with pytest.raises(TypeError, match="not both"):
        emdstar.mor(model="linear", stiffness=1e4, damping=1.0, restitution=0.5, radius=0.01,
                    density=2500.0, speed=1.0, eccentricity=0.0)
    assert emdstar.__version__.count(".") == 2
