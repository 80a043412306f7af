#!/usr/bin/env python3
"""Tests of compare_bags.py against known perturbations (issue 7).

Every bag comes from make_synthetic_bags.py: the machine bag is the simulation
bag with a perturbation the test chooses, so each expected figure follows from
that perturbation (and the generator's closed forms), not from earlier output
of the tool. Each assertion states its tolerance and why.

Run: python3 test/tools/test_compare_bags.py [--text]; registered for ctest in
CMakeLists.txt (JUnit result via rosunit). Installed.test_catkin_script needs the
devel space sourced (ctest does that): . .ws/devel/setup.bash
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
TOOLS = os.path.normpath(os.path.join(HERE, "..", "..", "src", "tools"))
COMPARE = os.path.join(TOOLS, "compare_bags.py")
GENERATE = os.path.join(TOOLS, "make_synthetic_bags.py")
sys.path.insert(0, TOOLS)
import make_synthetic_bags as gen  # noqa: E402  (the closed forms, for expected values)

N_SAMPLES = 501          # 2 s at 250 Hz (the generator's defaults)
RPM = 60 / (2 * math.pi)


def run(cmd):
    p = subprocess.run([sys.executable] + cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       universal_newlines=True)
    return p.returncode, p.stdout, p.stderr


class Base(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="compare_bags_test_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def make(cls, name, *perturbation, combined=True):
        """Bag(s) with the given perturbation; returns the compare_bags inputs."""
        if combined:
            path = os.path.join(cls.tmp, name + ".bag")
            rc, _, err = run([GENERATE, "--combined-bag", path] + list(perturbation))
            assert rc == 0, err
            return [path]
        sim, mach = (os.path.join(cls.tmp, name + s + ".bag") for s in ("_sim", "_machine"))
        rc, _, err = run([GENERATE, "--sim-bag", sim, "--machine-bag", mach] + list(perturbation))
        assert rc == 0, err
        return ["--machine", mach, "--sim", sim]

    def compare(self, inputs, *extra, plots=False):
        out = tempfile.mkdtemp(dir=self.tmp)
        rc, stdout, err = run([COMPARE] + inputs + ["--out", out] + list(extra)
                              + ([] if plots else ["--no-plots"]))
        self.assertEqual(rc, 0, "compare_bags failed: " + err)
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f), out

    def fails(self, inputs, *extra):
        out = tempfile.mkdtemp(dir=self.tmp)
        rc, _, err = run([COMPARE] + inputs + ["--out", out, "--no-plots"] + list(extra))
        self.assertEqual(rc, 2, "expected exit 2, got %d; stderr: %s" % (rc, err))
        self.assertFalse(os.path.exists(os.path.join(out, "summary.json")))
        self.assertFalse(os.path.exists(os.path.join(out, "summary.md")))
        return err


class TensionOffsetNoise(Base):
    """Offset 2 N and Gaussian noise sigma 0.2 N, no time shift: sim - machine
    = -2 N - noise exactly at every stamp."""
    OFFSET, SIGMA = 2.0, 0.2

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.bag = cls.make("offset", "--tension-offset", str(cls.OFFSET),
                           "--tension-noise", str(cls.SIGMA), "--seed", "7")

    def test_mean_offset_rms_peak(self):
        s, _ = self.compare(self.bag)
        t = s["tension"]
        self.assertGreaterEqual(t["samples"], N_SAMPLES - 2)
        # Mean of -2 N - noise: its standard error is sigma / sqrt(500) = 0.009 N;
        # tolerance 0.05 N (5.6 standard errors).
        self.assertAlmostEqual(t["mean_offset_N"], -self.OFFSET, delta=0.05)
        # RMS = sqrt(offset^2 + sigma^2) = 2.010 N; its spread is dominated by the
        # noise mean's (2 offset 0.009 / (2 RMS) = 0.009 N): tolerance 0.04 N (4.5 of it).
        self.assertAlmostEqual(t["rms_N"], math.hypot(self.OFFSET, self.SIGMA), delta=0.04)
        # The scatter about the offset is the noise: sigma within 10 % (the
        # sample sigma's spread is sigma / sqrt(2 N) = 3 %).
        self.assertAlmostEqual(t["std_N"], self.SIGMA, delta=0.1 * self.SIGMA)
        # Peak: 2 N plus the largest of 500 noise samples, which lies between
        # 1.5 sigma and 5 sigma for any seed in practice.
        self.assertGreater(t["peak_N"], self.OFFSET + 1.5 * self.SIGMA)
        self.assertLess(t["peak_N"], self.OFFSET + 5 * self.SIGMA)
        # Percent of the machine's mean: the closed-form mean over the samples + 2 N.
        import numpy as np
        ts = np.arange(N_SAMPLES) / 250.0
        machine_mean = float(np.mean(gen.tension(ts))) + self.OFFSET
        self.assertAlmostEqual(t["machine_mean_N"], machine_mean, delta=0.05)
        self.assertAlmostEqual(t["mean_offset_pct"], -100 * self.OFFSET / machine_mean, delta=0.2)
        # No time shift: the lag is 0 within 0.5 ms.
        self.assertAlmostEqual(s["lag"]["lag_s"], 0.0, delta=5e-4)
        self.assertAlmostEqual(s["lag"]["spindle_speed_lag_s"], 0.0, delta=5e-4)
        # Same spindle: no speed error (below rounding).
        self.assertLess(s["spindle_speed"]["rms_rpm"], 1e-6)

    def test_angle_alignment_same_figures(self):
        # Without a time shift both alignments compare the same samples.
        s, _ = self.compare(self.bag, "--align", "angle")
        self.assertEqual(s["align"], "angle")
        self.assertAlmostEqual(s["tension"]["mean_offset_N"], -self.OFFSET, delta=0.05)
        self.assertAlmostEqual(s["tension"]["rms_N"], math.hypot(self.OFFSET, self.SIGMA), delta=0.04)


class TimeShift(Base):
    """The machine's stamps 5 ms late (two bags): the lag, and alignment by
    angle against alignment by time."""
    SHIFT, OFFSET, SIGMA = 0.005, 2.0, 0.2

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.bags = cls.make("shift", "--time-shift", str(cls.SHIFT), "--tension-offset", str(cls.OFFSET),
                            "--tension-noise", str(cls.SIGMA), combined=False)

    def test_lag(self):
        s, _ = self.compare(self.bags)
        # 5 ms is 1.25 samples at 250 Hz: sub-sample refinement is needed; within 0.5 ms.
        self.assertAlmostEqual(s["lag"]["lag_s"], self.SHIFT, delta=5e-4)
        self.assertAlmostEqual(s["lag"]["spindle_speed_lag_s"], self.SHIFT, delta=5e-4)

    def test_negative_lag(self):
        # The sign convention: a machine 3 ms early gives lag -3 ms.
        bags = self.make("early", "--time-shift", "-0.003", "--tension-noise", "0.2", combined=False)
        s, _ = self.compare(bags)
        self.assertAlmostEqual(s["lag"]["lag_s"], -0.003, delta=5e-4)
        self.assertAlmostEqual(s["lag"]["spindle_speed_lag_s"], -0.003, delta=5e-4)

    def test_lag_not_identifiable_under_noise(self):
        # Noise of 5 N swamps the sim's 1 N ripple: the least-squares minimum
        # would be a lag that means nothing. It is reported as not estimated,
        # with the reason; the spindle speed still gives the shift.
        bags = self.make("noisy", "--time-shift", str(self.SHIFT), "--tension-noise", "5",
                         combined=False)
        s, _ = self.compare(bags)
        self.assertIsNone(s["lag"]["lag_s"])
        self.assertTrue(any("not identifiable" in n for n in s["notes"]), s["notes"])
        self.assertAlmostEqual(s["lag"]["spindle_speed_lag_s"], self.SHIFT, delta=5e-4)

    def test_angle_alignment_removes_the_shift(self):
        s, _ = self.compare(self.bags, "--align", "angle")
        # Machine tension and spindle are shifted together: at equal angles the
        # machine tension is the sim's + 2 N + noise (tolerances as above).
        self.assertAlmostEqual(s["tension"]["mean_offset_N"], -self.OFFSET, delta=0.05)
        self.assertAlmostEqual(s["tension"]["rms_N"], math.hypot(self.OFFSET, self.SIGMA), delta=0.04)
        # Speed against angle is identical (below 0.01 rpm: interpolation only).
        self.assertLess(s["spindle_speed"]["rms_rpm"], 0.01)

    def test_time_alignment_sees_the_shift(self):
        s, _ = self.compare(self.bags, "--align", "time")
        # During the 0.5 s ramp (of 2 s) the speed is off by alpha * shift
        # (alpha = 1200 rpm / 0.5 s), 0 after: RMS = alpha shift sqrt(0.5 / 2) = 6.0 rpm,
        # within 5 % (the ramp's corner).
        alpha = gen.OMEGA_MAX / gen.T_RAMP
        expected = alpha * self.SHIFT * math.sqrt(0.25) * RPM
        self.assertAlmostEqual(s["spindle_speed"]["rms_rpm"], expected, delta=0.05 * expected)
        # The ripple's phase error adds to the offset: the RMS is well above
        # sqrt(offset^2 + sigma^2) (the hold alone would give 2.17 N).
        self.assertGreater(s["tension"]["rms_N"], math.hypot(self.OFFSET, self.SIGMA) + 0.05)


class Profile(Base):
    """Radial profile offset 0.1 mm and bulge scale: profile error and bulging."""

    def test_no_perturbation(self):
        s, out = self.compare(self.make("clean"), plots=True)
        p = s["profile"]
        # The machine points lie on the same helix, off the sim's mass points: only
        # the polyline's chord sag remains, <= l^2 / (8 r) = 0.003 mm.
        self.assertTrue(p["compared"])
        self.assertLess(p["all_pairs"]["max_mm"], 0.004)
        self.assertAlmostEqual(p["bulging"]["diff_mm"], 0.0, delta=1e-3)
        self.assertAlmostEqual(p["bulging"]["sim_mm"], gen.BULGE * 1e3, delta=1e-3)
        for name in ("tension_vs_angle.png", "profile_overlay.png", "spindle_speed.png"):
            with open(os.path.join(out, name), "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n", name)
        with open(os.path.join(out, "summary.md")) as f:
            self.assertIn("profile RMS", f.read())

    def test_offset(self):
        for align in ("time", "angle"):
            s, _ = self.compare(self.make("poff", "--profile-offset-mm", "0.1", "--time-shift", "0.005"),
                                "--align", align)
            p = s["profile"]
            # Every measured point 0.1 mm outside the wire: RMS and largest 0.1 mm
            # within 0.01 mm (chord sag 0.003 mm).
            self.assertAlmostEqual(p["last"]["rms_mm"], 0.1, delta=0.01, msg=align)
            self.assertAlmostEqual(p["all_pairs"]["rms_mm"], 0.1, delta=0.01, msg=align)
            self.assertAlmostEqual(p["all_pairs"]["max_mm"], 0.1, delta=0.01, msg=align)
            self.assertGreaterEqual(p["pairs"], 15)
            # Bulging: machine 0.3 + 0.1 mm, sim 0.3 mm: sim - machine = -0.1 mm (-25 %),
            # within 0.002 mm (float32 coordinates).
            b = p["bulging"]
            self.assertAlmostEqual(b["machine_mm"], 0.4, delta=0.002)
            self.assertAlmostEqual(b["diff_mm"], -0.1, delta=0.002)
            self.assertAlmostEqual(b["diff_pct"], -25.0, delta=0.5)

    def test_bulge_scale(self):
        s, _ = self.compare(self.make("bulge", "--bulge-scale", "1.5"))
        b = s["profile"]["bulging"]
        # Machine stand-off 1.5 x 0.3 mm: difference -0.15 mm (-33.3 %), within 0.002 mm.
        self.assertAlmostEqual(b["machine_mm"], 0.45, delta=0.002)
        self.assertAlmostEqual(b["diff_mm"], -0.15, delta=0.002)
        self.assertAlmostEqual(b["diff_pct"], -100 * 0.15 / 0.45, delta=0.5)
        # The profile error is the extra stand-off: largest 0.15 mm at the bulge (within 0.01 mm).
        self.assertAlmostEqual(s["profile"]["last"]["max_mm"], 0.15, delta=0.01)

    def test_no_stand_off(self):
        s, out = self.compare(self.make("noso", "--drop-stand-off", "--profile-offset-mm", "0.1"))
        self.assertFalse(s["profile"]["bulging"]["compared"])
        self.assertIn("no stand_off", s["profile"]["bulging"]["reason"])
        self.assertAlmostEqual(s["profile"]["last"]["rms_mm"], 0.1, delta=0.01)
        with open(os.path.join(out, "summary.md")) as f:
            self.assertIn("machine/profile has no stand_off field", f.read())


class FromSimBag(Base):
    """--from-sim-bag: the perturbation applied to an existing bag's sim/* topics."""

    def test_perturb_existing_bag(self):
        sim = os.path.join(self.tmp, "run.bag")
        rc, _, err = run([GENERATE, "--sim-bag", sim])
        self.assertEqual(rc, 0, err)
        mach = os.path.join(self.tmp, "run_machine.bag")
        rc, _, err = run([GENERATE, "--from-sim-bag", sim, "--machine-bag", mach, "--tension-offset", "1.0",
                          "--time-shift", "0.002", "--profile-offset-mm", "0.1"])
        self.assertEqual(rc, 0, err)
        s, _ = self.compare(["--machine", mach, "--sim", sim], "--align", "angle")
        # Offset 1 N without noise: exact up to interpolation, within 0.05 N.
        self.assertAlmostEqual(s["tension"]["mean_offset_N"], -1.0, delta=0.05)
        self.assertAlmostEqual(s["lag"]["lag_s"], 0.002, delta=5e-4)
        # Here the machine points are the sim's own, moved out 0.1 mm.
        self.assertAlmostEqual(s["profile"]["all_pairs"]["rms_mm"], 0.1, delta=0.01)

    def test_reference_sim_bag(self):
        # A simulated run as the reference: its sim/* topics take the
        # machine's part. Against itself every error is zero. (A real cell's
        # bag goes the same way in test/ros/test_exit_at_end.cpp.)
        ref = os.path.join(self.tmp, "variant_a.bag")
        rc, _, err = run([GENERATE, "--sim-bag", ref])
        self.assertEqual(rc, 0, err)
        s, out = self.compare(["--reference", ref, "--sim", ref])
        self.assertEqual(s["tension"]["rms_N"], 0.0)
        # Outputs get the usual mode (0644 under umask 022), not mkstemp's 0600.
        umask = os.umask(0)
        os.umask(umask)
        for name in ("summary.json", "summary.md"):
            mode = os.stat(os.path.join(out, name)).st_mode & 0o777
            self.assertEqual(mode, 0o666 & ~umask, name)
        self.assertEqual(s["spindle_speed"]["rms_rad_per_s"], 0.0)
        self.assertEqual(s["machine_bag"], ref)


class BadInput(Base):
    """Exit 2 with the culprit named, and no summary left behind."""

    def test_missing_bag(self):
        err = self.fails([os.path.join(self.tmp, "nope.bag")])
        self.assertIn("no such bag", err)
        self.assertIn("nope.bag", err)

    def test_missing_topic(self):
        err = self.fails(self.make("notension", "--drop-topic", "tension/measured"))
        self.assertIn("machine/tension/measured", err)
        self.assertIn("missing", err)

    def test_non_monotonic(self):
        err = self.fails(self.make("nonmono", "--non-monotonic", "spindle/state"))
        self.assertIn("machine/spindle/state", err)
        # The generator swaps messages n/2 and n/2 + 1 (n = 501): message 251 goes back.
        self.assertIn("message 251", err)

    def test_no_overlap(self):
        err = self.fails(self.make("late", "--time-shift", "10"))
        self.assertIn("no time overlap", err)

    def test_joint_missing(self):
        err = self.fails(self.make("nojoint", "--rename-joint", "spindle_1"))
        self.assertIn("machine/spindle/state", err)
        self.assertIn("no joint 'spindle'", err)

    def test_too_few_samples(self):
        err = self.fails(self.make("short", "--duration", "0.02"))
        self.assertIn("too few samples", err)

    def test_reference_excludes_machine(self):
        bag = self.make("good")[0]
        rc, _, err = run([COMPARE, "--machine", bag, "--reference", bag, "--sim", bag,
                          "--out", os.path.join(self.tmp, "o")])
        self.assertEqual(rc, 2, err)
        self.assertIn("--machine and --reference exclude each other", err)

    def test_stale_summary_removed(self):
        good, out = self.compare(self.make("good"))
        rc, _, err = run([COMPARE, os.path.join(self.tmp, "nope.bag"), "--out", out])
        self.assertEqual(rc, 2, err)
        self.assertFalse(os.path.exists(os.path.join(out, "summary.json")))
        self.assertFalse(os.path.exists(os.path.join(out, "summary.md")))


class Installed(unittest.TestCase):
    def test_catkin_script(self):
        # The catkin script in the devel space (what roslaunch and, in a plain
        # workspace, rosrun run): catkin_find lists it and it runs.
        for name in ("compare_bags.py", "make_synthetic_bags.py"):
            p = subprocess.run(["catkin_find", "--libexec", "coil_winding_sim", name],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
            paths = p.stdout.split()
            self.assertTrue(paths, "catkin_find found no %s: %s" % (name, p.stderr))
            q = subprocess.run([paths[0], "-h"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               universal_newlines=True)
            self.assertEqual(q.returncode, 0, q.stderr)
            self.assertIn("--machine-bag" if name.startswith("make") else "--align", q.stdout)


def suite():
    loader = unittest.TestLoader()
    return unittest.TestSuite(loader.loadTestsFromTestCase(c) for c in
                              (TensionOffsetNoise, TimeShift, Profile, FromSimBag, BadInput, Installed))


if __name__ == "__main__":
    if "--gtest_output" in " ".join(sys.argv) or "--text" in sys.argv:
        import rosunit
        rosunit.unitrun("coil_winding_sim", "compare_bags", "test_compare_bags.suite")
    else:
        unittest.main()
