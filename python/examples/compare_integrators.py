"""Error against time for two integrators on one scene, loaded once: the notebook example of
docs/python.md. Writes a log-log plot (matplotlib) and prints the table it plots.

    PYTHONPATH=build/python python3 python/examples/compare_integrators.py \
        scenes/whitted.gltf --out error-vs-time.png
"""

import argparse

import matplotlib

matplotlib.use("Agg")  # no display needed: the plot goes to a file
import matplotlib.pyplot as plt  # noqa: E402

import prism  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--out", default="error-vs-time.png")
    parser.add_argument("--integrators", default="shadow,whitted")
    parser.add_argument("--resolution", default="160x120")
    parser.add_argument("--reference-spp", type=int, default=256)
    parser.add_argument("--spp", default="1,2,4,8,16")
    args = parser.parse_args()

    width, height = (int(v) for v in args.resolution.split("x"))
    session = prism.Session(args.scene)
    print(f"loaded {args.scene} in {session.load_seconds:.3f} s on {session.threads} threads")

    figure, axes = plt.subplots(figsize=(6, 4))
    for integrator in args.integrators.split(","):
        reference = session.render(integrator=integrator, spp=args.reference_spp,
                                   resolution=(width, height))
        times, errors = [], []
        for spp in (int(s) for s in args.spp.split(",")):
            render = session.render(integrator=integrator, spp=spp, resolution=(width, height))
            error = prism.compare_images(render.image, reference.image)["relmse"]
            times.append(render.seconds)
            errors.append(error)
            print(f"{integrator:8} {spp:4} spp  {render.seconds:8.4f} s  relMSE {error:.3e}")
        axes.loglog(times, errors, "o-", label=integrator)
    axes.set_xlabel("render time (s)")
    axes.set_ylabel(f"relMSE against {args.reference_spp} spp")
    axes.legend()
    figure.tight_layout()
    figure.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
