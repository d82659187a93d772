"""brdffit.dask on a LocalCluster of two worker processes (loopback only):
files and texel maps give results identical to the same fits in this
process, bad items are reported in their rows, the fitted parameters are
the ones the data were made from, and a worker killed mid-run loses and
duplicates nothing. Exits with 77 (skipped) when dask is not importable."""

import os
import signal
import sys
import tempfile
import time
import unittest

try:
    import distributed
    from distributed import Client, LocalCluster
except ImportError as exc:
    print("python_test_dask: SKIPPED: dask/distributed not importable (%s); Debian: "
          "apt-get install python3-dask python3-distributed" % exc)
    sys.exit(77)

import numpy as np

import brdffit
import brdffit.dask as bd

import support

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data")
AXES = (support.radians(np.arange(0.0, 76.0, 5.0)), support.radians(np.arange(0.0, 81.0, 4.0)),
        support.radians(np.arange(0.0, 181.0, 10.0)))  # 16 * 21 * 19 = 6384 samples


def texel_map(n, seed=3):
    """``n`` texels of Ashikhmin-Shirley data from known parameters."""
    model = brdffit.Model.builtin("ashikhmin-shirley")
    angles = support.grid_angles(AXES)
    rng = np.random.default_rng(seed)
    truth = np.array([model.pack_params({"ns": rng.uniform(10.0, 200.0),
                                         "cd": rng.uniform(0.05, 0.5, 3),
                                         "cs": rng.uniform(0.05, 0.5, 3)}, 3)
                      for _ in range(n)])
    values = np.array([model.eval_angles(*angles, p, 3).T for p in truth])
    return truth, values


def assert_same(test, a, b):
    test.assertEqual(a.names, b.names)
    np.testing.assert_array_equal(a.ok, b.ok)
    for ra, rb in zip(a.rows, b.rows):  # files may differ in channel count
        for key in ("params", "std_errors"):
            np.testing.assert_array_equal(ra[key], rb[key])
    np.testing.assert_array_equal(a.rms, b.rms)
    np.testing.assert_array_equal(a.iterations, b.iterations)
    test.assertEqual([r["error"] for r in a.rows], [r["error"] for r in b.rows])


class GeometryTest(unittest.TestCase):
    def test_unaligned_arrays(self):
        """Arrays unpickled on a worker may be unaligned (the sanitized build
        reports a misaligned load in the library if they reach it)."""
        raw = np.concatenate([a for a in AXES]).tobytes()
        buf = bytearray(len(raw) + 1)
        buf[1:] = raw
        flat = np.frombuffer(buf, dtype=np.float64, offset=1)
        self.assertFalse(flat.flags.aligned)
        sizes = np.cumsum([0] + [a.size for a in AXES])
        unaligned = [flat[sizes[k]:sizes[k + 1]] for k in range(3)]
        geometry = bd.Geometry(regular=AXES)
        geometry.arrays = tuple(unaligned)  # as unpickling may leave them
        truth, values = texel_map(1)
        with geometry.grid(values[0]) as grid:
            self.assertEqual(grid.sample_count, geometry.sample_count)
            np.testing.assert_array_equal(grid.axes[0], AXES[0])


class OptionsTest(unittest.TestCase):
    def test_objective_and_plausible_reach_the_fits(self):
        """A batch's ``objective`` and ``plausible`` reach every fit; without
        them the fits take the library's defaults (cube-root, 1)."""
        truth, values = texel_map(2)
        geometry = bd.Geometry(regular=AXES)
        base = {"pipeline": "joint", "start": truth[0] * 1.2, "max_iterations": 1}
        cost = {}
        for objective in (None, "squares", "cube-root"):
            options = dict(base) if objective is None else dict(base, objective=objective)
            cost[objective] = bd.fit_texels_local(geometry, values, options=options).rows[0]["cost"]
            with geometry.grid(values[0]) as grid:
                with brdffit.Fit(grid, brdffit.Model.builtin("ashikhmin-shirley"),
                                 **options) as fit:
                    self.assertEqual(fit.run().error("cost"), cost[objective])
        self.assertEqual(cost[None], cost["cube-root"])
        self.assertNotEqual(cost["squares"], cost["cube-root"])
        table = bd.fit_texels_local(geometry, values, options={"plausible": 0})
        self.assertEqual(len(table.failed()), 0)


class ClusterTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                   host="127.0.0.1", dashboard_address=None,
                                   silence_logs=50)
        cls.client = Client(cls.cluster)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.cluster.close()

    def test_files_with_bad_items(self):
        with tempfile.TemporaryDirectory() as tmp:
            bad = os.path.join(tmp, "bad.csv")
            with open(bad, "w") as f:
                f.write("theta_i,phi_i,theta_o,phi_o,r\n1,2,3,x,5\n")
            good = [os.path.join(DATA, "sample_grid.csv"),
                    os.path.join(DATA, "sample_scattered.csv")]
            paths = good * 5 + [bad, os.path.join(tmp, "missing.csv")] + good
            got = bd.fit_files(self.client, paths, per_task=3)
            local = bd.fit_files_local(paths)
        assert_same(self, got, local)
        self.assertEqual(len(got), len(paths))
        failed = dict(got.failed())
        self.assertEqual(sorted(failed), sorted([bad, os.path.join(tmp, "missing.csv")]))
        self.assertIn("BRDFFIT_E_PARSE", failed[bad])
        self.assertIn("BRDFFIT_E_IO", failed[os.path.join(tmp, "missing.csv")])
        self.assertTrue(all(got.rows[k]["params"] is None for k in np.flatnonzero(~got.ok)))
        self.assertTrue(np.all(np.isfinite(got.rms[got.ok])))

    def test_progress_and_options(self):
        truth, values = texel_map(12)
        geometry = bd.Geometry(regular=AXES)
        options = {"pipeline": "joint", "damping": "marquardt", "fixed": ["ns"],
                   "start": {"ns": 50.0}}
        got = bd.fit_texels(self.client, geometry, values, options=options, per_task=5,
                            progress=True)
        local = bd.fit_texels_local(geometry, values, options=options)
        assert_same(self, got, local)
        np.testing.assert_allclose(got.params[:, 0], 50.0, rtol=1e-12)  # held
        with self.assertRaises(ValueError):  # a mistake fails at once, not per row
            bd.fit_texels(self.client, geometry, values, options={"callback": print})

    def test_texels_identical_to_local_and_recovered(self):
        truth, values = texel_map(40)
        values[7, 100:200] = np.nan  # missing values in one texel
        values[9] = np.nan           # a texel with no data: reported, not fatal
        geometry = bd.Geometry(regular=AXES)
        got = bd.fit_texels(self.client, geometry, values, per_task=6)
        local = bd.fit_texels_local(geometry, values)
        assert_same(self, got, local)
        self.assertEqual([n for n, _ in got.failed()], [9])
        ok = got.ok
        rel = np.abs(got.params[ok] - truth[ok]) / truth[ok]
        self.assertLess(rel.max(), 1e-6)

    def test_model_from_a_function(self):
        truth, values = texel_map(6, seed=6)
        geometry = bd.Geometry(regular=AXES)
        got = bd.fit_texels(self.client, geometry, values, per_task=4,
                            model=lambda: brdffit.Model.builtin("ashikhmin-shirley"),
                            options={"pipeline": "joint"})
        local = bd.fit_texels_local(geometry, values, options={"pipeline": "joint"})
        assert_same(self, got, local)
        self.assertLess((np.abs(got.params - truth) / truth).max(), 1e-6)

    def test_texel_file(self):
        truth, values = texel_map(20, seed=4)
        geometry = bd.Geometry(regular=AXES)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "map.npy")
            np.save(path, values)
            got = bd.fit_texels(self.client, geometry, path, per_task=6)
        assert_same(self, got, bd.fit_texels_local(geometry, values))
        self.assertLess((np.abs(got.params - truth) / truth).max(), 1e-6)

    def test_worker_killed_mid_run(self):
        truth, values = texel_map(160, seed=5)
        geometry = bd.Geometry(regular=AXES)
        local = bd.fit_texels_local(geometry, values)
        pids = self.client.run(os.getpid)
        job = bd.submit_texels(self.client, geometry, values, per_task=4)
        deadline = time.monotonic() + 60.0
        while sum(f.done() for f in job.futures) < 4 and time.monotonic() < deadline:
            time.sleep(0.002)
        done_at_kill = sum(f.done() for f in job.futures)
        victim = sorted(pids.values())[0]
        os.kill(victim, signal.SIGKILL)
        got = job.result()
        self.assertLess(done_at_kill, len(job.futures), "the run ended before the kill")
        assert_same(self, got, local)
        self.assertEqual(len(got), 160)
        self.client.wait_for_workers(2, timeout=60)
        self.assertNotIn(victim, self.client.run(os.getpid).values())
        print("worker %d killed with %d of %d tasks done" % (victim, done_at_kill,
                                                             len(job.futures)))


if __name__ == "__main__":
    print("distributed", distributed.__version__)
    unittest.main()
