#!/usr/bin/python3
"""granulab's interface laws against LAMMPS' pair_style granular on the same spheres (docs/model.md, "Interface laws";
bench/README.md, "Interface laws against LAMMPS"): two aligned cubes at rest, pressed in and pulled back out past
JKR's break point, hertz/material, dmt and jkr. bench/lammps_laws_compare.py fails unless every force where either
code has one agrees within 1 % (measured: 2.6e-8, the atoms' positions), DMT's and JKR's largest tension and JKR's
snap and break points included.

LAMMPS (Debian's lammps) is installed when missing and root; the test is skipped otherwise. About two seconds.
"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests"))
from debian_packages import install_missing  # noqa: E402  (tests/debian_packages.py)


class InterfaceLawsAgainstLammps(unittest.TestCase):
    def test_two_cubes_agree_within_one_percent(self):
        install_missing(["lammps"], "LAMMPS")
        if not shutil.which("lmp"):
            self.skipTest("lammps is installed but gives no lmp")
        out = tempfile.mkdtemp(prefix="granulab_laws_")
        try:
            run = subprocess.run([sys.executable, os.path.join(ROOT, "bench", "lammps_laws_compare.py"), "--out", out,
                                  "--lmp", shutil.which("lmp")],
                                 capture_output=True, text=True, timeout=600,
                                 env=dict(os.environ, BUILD=os.environ.get("BUILD", os.path.join(ROOT, "build"))))
            print(run.stdout[-3000:])
            self.assertEqual(run.returncode, 0, run.stdout[-3000:] + run.stderr[-3000:])
            for law in ("hertz/material", "dmt", "jkr"):
                self.assertIn(law, run.stdout)
        finally:
            shutil.rmtree(out, ignore_errors=True)


if __name__ == "__main__":
    import skip_aware  # noqa: E402  (tests/skip_aware.py)
    skip_aware.main()
