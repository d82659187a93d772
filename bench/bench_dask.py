#!/usr/bin/env python3
"""Batch fits with brdffit.dask: fits per second of a local loop and of a
LocalCluster with 1 and 2 worker processes (one thread each), and the
overhead per task against the local loop (docs/python.md, Figures).

    BRDFFIT_LIBRARY=build/libbrdffit.so.0 PYTHONPATH=bindings/python \\
        /usr/bin/python3 bench/bench_dask.py [--texels 512] [--per-task 32] [--repeat 3]

The work is a texel map: every texel an Ashikhmin-Shirley measurement over
the same regular layout (16 x 21 x 19 = 6384 samples, 3 channels) made from
its own known parameters, fitted with the default (auto) pipeline under the
squares objective (``OPTIONS``: the objective of the figures in docs/python.md,
whatever the library's default). Each
figure is the best of --repeat runs after a warm-up run; a cluster run
includes scattering the geometry, shipping the values (an array in memory:
with the tasks, through the scheduler; a .npy map file: each worker reads
its tiles) and gathering the table. It also times tasks of a single fit of almost no work (the round trip of a
task). --smoke runs a tiny problem once on one worker (checks that the script
works; nothing it prints is a figure).
"""

import argparse
import math
import os
import tempfile
import time

import numpy as np

import brdffit
import brdffit.dask as bd

#: Every fit's options: the squares objective, so figures compare across versions.
OPTIONS = {"objective": "squares"}

AXES = tuple(np.arange(lo, hi, step) * (math.pi / 180.0)
             for lo, hi, step in ((0.0, 76.0, 5.0), (0.0, 81.0, 4.0), (0.0, 181.0, 10.0)))


def texel_map(n):
    model = brdffit.Model.builtin("ashikhmin-shirley")
    ti, to, po = (a.reshape(-1) for a in np.meshgrid(*AXES, indexing="ij"))
    rng = np.random.default_rng(1)
    values = np.empty((n, ti.size, 3))
    for k in range(n):
        p = model.pack_params({"ns": rng.uniform(10.0, 200.0), "cd": rng.uniform(0.05, 0.5, 3),
                               "cs": rng.uniform(0.05, 0.5, 3)}, 3)
        values[k] = model.eval_angles(ti, np.full_like(ti, math.pi), to, po, p, 3).T
    return values


def best_time(fn, repeat):
    fn()  # warm-up: imports and caches on the workers
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        table = fn()
        times.append(time.perf_counter() - t0)
        if len(table.failed()):
            raise SystemExit("fits failed: %s" % table.failed()[:3])
    return min(times)


def cluster_time(n_workers, geometry, values, per_task, repeat, model="ashikhmin-shirley"):
    """Best time of fit_texels on a fresh cluster of ``n_workers``."""
    from distributed import Client, LocalCluster
    with LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                      host="127.0.0.1", dashboard_address=None, silence_logs=50) as cluster, \
            Client(cluster) as client:
        return best_time(lambda: bd.fit_texels(client, geometry, values, model, options=OPTIONS,
                                               per_task=per_task), repeat)


def tiny_batch(n):
    """``n`` distinct one-channel texels over an 18-sample geometry (distinct,
    so no two tasks are the same pure task): a fit costs almost nothing."""
    axes = (np.array([0.0, 0.5]), np.array([0.0, 0.4, 0.8]), np.array([0.0, 1.5, 3.0]))
    values = np.linspace(0.1, 0.2, 18)[None, :] * (1.0 + 1e-3 * np.arange(n))[:, None]
    return bd.Geometry(regular=axes), values[:, :, None]


def report_tiny(args):
    """The round trip of a task of one tiny fit on 1 worker, against the fit."""
    n_tiny = 100
    tiny = tiny_batch(n_tiny)
    t = cluster_time(1, tiny[0], tiny[1], 1, args.repeat, "lambert")
    alone = best_time(lambda: bd.fit_texels_local(*tiny, "lambert", options=OPTIONS), args.repeat)
    print("round trip of a task of one tiny fit, 1 worker: %.2f ms (the fit alone, locally: "
          "%.3f ms)" % (1e3 * t / n_tiny, 1e3 * alone / n_tiny))


def report_source(what, geometry, source, local, args):
    """Fits per second on 1 and 2 workers for one form of the map."""
    n, n_tasks = args.texels, math.ceil(args.texels / args.per_task)
    one = cluster_time(1, geometry, source, args.per_task, args.repeat)
    print("1 worker,  %-10s %8.1f fits/s  (%.3f s)" % (what, n / one, one))
    print("overhead per task, %s (1 worker against the local loop): %.2f ms"
          % (what, 1e3 * (one - local) / n_tasks))
    if not args.smoke:
        two = cluster_time(2, geometry, source, args.per_task, args.repeat)
        print("2 workers, %-10s %8.1f fits/s  (%.3f s)  %.2fx 1 worker"
              % (what, n / two, two, one / two))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--texels", type=int, default=512)
    ap.add_argument("--per-task", type=int, default=32)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--smoke", action="store_true")
    args = ap.parse_args()
    if args.smoke:
        args.texels, args.per_task, args.repeat = 8, 4, 1
    try:
        import distributed  # noqa: F401
    except ImportError as exc:
        print("bench_dask: SKIPPED: dask/distributed not importable (%s)" % exc)
        raise SystemExit(77)
    values = texel_map(args.texels)
    geometry = bd.Geometry(regular=AXES)
    print("brdffit.dask: %d texels of %d samples, %d per task (%d tasks); %d CPUs, load %.2f"
          % (args.texels, geometry.sample_count, args.per_task,
             math.ceil(args.texels / args.per_task), os.cpu_count(), os.getloadavg()[0]))
    local = best_time(lambda: bd.fit_texels_local(geometry, values, options=OPTIONS),
                      args.repeat)
    print("local loop            %8.1f fits/s  (%.3f s)" % (args.texels / local, local))
    report_tiny(args)
    report_source("array", geometry, values, local, args)
    if not args.smoke:
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "map.npy")
            np.save(path, values)
            report_source("map file", geometry, path, local, args)
    print("load average after the runs: %.2f" % os.getloadavg()[0])


if __name__ == "__main__":
    main()
