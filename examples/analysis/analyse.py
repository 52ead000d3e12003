"""A trajectory analysed with the field's libraries: g(r), the mean squared
displacement and the speed distribution of a GSD file.

    python examples/analysis/analyse.py [RUN.gsd] [--png analysis.png]

Without a file it first runs examples/analysis/gas.toml (a dilute elastic gas) with
``emdstar.run``, writing ``gas.gsd``. Then:

- reads the frames with ``gsd`` (HOOMD-blue's reader: emdstar writes HOOMD's schema);
- g(r) of the last frame with ``freud.density.RDF``;
- the MSD with ``freud.msd.MSD`` from positions and the image flags
  (``particles/image``), which count each sphere's crossings of the periodic faces;
- the diffusion coefficient from the MSD's late slope, against Enskog's;
- the speed distribution against Maxwell's at the measured temperature, with numpy
  (freud has no velocity statistics; a histogram needs nothing more);

and writes the three panels to a PNG. Prints the figures it checks as JSON.
"""

import argparse
import json
import os
import sys

import numpy as np


def simulate(path):
    import emdstar

    here = os.path.dirname(os.path.abspath(__file__))
    emdstar.run(os.path.join(here, "gas.toml"), engine="emdstar", trajectory=path,
                log="none", frames=2, progress=False)


def analyse(path, png):
    import freud
    import gsd.hoomd
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with gsd.hoomd.open(path, "r") as traj:
        frames = list(traj)
    # emdstar logs each frame's time (s) as log/time; other writers' frames count steps.
    times = np.array([f.log["time"][0] if "time" in f.log else f.configuration.step
                      for f in frames], dtype=float)
    last = frames[-1]
    lx, ly, lz = (float(x) for x in last.configuration.box[:3])
    box = freud.box.Box(lx, ly, lz)
    diameter = float(last.particles.diameter[0])
    mass = float(last.particles.mass[0])

    # g(r): zero inside the contact distance, about 1 beyond a few diameters in a gas.
    rdf = freud.density.RDF(bins=100, r_max=min(lx, ly, lz) / 2.5)
    for f in frames[len(frames) // 2:]:
        rdf.compute(system=(box, f.particles.position), reset=False)
    r, g = rdf.bin_centers, rdf.rdf

    # MSD from the image flags.
    pos = np.stack([f.particles.position for f in frames]).astype(np.float64)
    img = np.stack([f.particles.image for f in frames]).astype(np.int32)
    msd = freud.msd.MSD(box=box, mode="direct").compute(positions=pos, images=img).msd
    lag = times - times[0]

    # Speeds against Maxwell's distribution at the measured temperature.
    vel = np.concatenate([f.particles.velocity for f in frames[len(frames) // 2:]]).astype(np.float64)
    speed = np.linalg.norm(vel, axis=1)
    kT = mass * np.mean(speed**2) / 3.0
    hist, edges = np.histogram(speed, bins=40, density=True)
    v = 0.5 * (edges[1:] + edges[:-1])
    maxwell = 4 * np.pi * v**2 * (mass / (2 * np.pi * kT)) ** 1.5 * np.exp(-mass * v**2 / (2 * kT))

    fig, ax = plt.subplots(1, 3, figsize=(13, 4))
    ax[0].plot(r / diameter, g)
    ax[0].axhline(1.0, color="gray", lw=0.5)
    ax[0].set(xlabel="r / d", ylabel="g(r)", title="pair correlation (freud)")
    ax[1].loglog(lag[1:], msd[1:], label="from image flags (freud)")
    ax[1].loglog(lag[1:], 3 * kT / mass * lag[1:] ** 2, "--", label="ballistic 3kT t²/m")
    ax[1].set(xlabel="t [s]", ylabel="MSD [m²]", title="mean squared displacement")
    ax[1].legend()
    ax[2].plot(v, hist, "o", ms=3, label="emdstar")
    ax[2].plot(v, maxwell, label=f"Maxwell, T = {kT:.3g} J")
    ax[2].set(xlabel="|v| [m/s]", ylabel="p(|v|)", title="speed distribution (numpy)")
    ax[2].legend()
    fig.tight_layout()
    fig.savefig(png, dpi=110)

    # Diffusion: the MSD's late slope against Enskog's D = 3/(8 n d² g(d)) √(kT/(πm))
    # (Chapman & Cowling), with Carnahan-Starling's g(d) = (1 - η/2)/(1 - η)³.
    n = len(last.particles.position) / (lx * ly * lz)
    eta = n * np.pi * diameter**3 / 6
    enskog = 3 / (8 * n * diameter**2) * (1 - eta) ** 3 / (1 - eta / 2) * np.sqrt(kT / (np.pi * mass))
    late = lag >= lag[-1] / 2
    slope = np.polyfit(lag[late], msd[late], 1)[0]

    inside = g[r < 0.95 * diameter]
    far = g[r > 3 * diameter]
    figures = {
        "frames": len(frames),
        "g_inside_contact_max": float(inside.max()) if inside.size else 0.0,
        "g_far_mean": float(far.mean()),
        "msd_final": float(msd[-1]),
        "ballistic_ratio_first_lag": float(msd[1] / (3 * kT / mass * lag[1] ** 2)),
        "diffusion": float(slope / 6),
        "diffusion_enskog": float(enskog),
        "speed_hist_vs_maxwell_max_abs": float(np.max(np.abs(hist - maxwell))),
        "maxwell_peak": float(maxwell.max()),
        "png": png,
    }
    return figures


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("gsd", nargs="?", help="a GSD trajectory (default: run gas.toml first)")
    p.add_argument("--png", default="analysis.png")
    args = p.parse_args()
    path = args.gsd
    if path is None:
        path = "gas.gsd"
        if os.path.exists(path):
            sys.exit(f"{path} exists: give it as the argument, or remove it to run the gas again")
        simulate(path)
    print(json.dumps(analyse(path, args.png), indent=1))


if __name__ == "__main__":
    main()
