"""``mpiexec -n 2`` gives the same load and peak pressure as a serial run (relative 1e-8).

Both runs solve the same displacement-controlled Hertz scene (small mesh, h = a/10) to SNES rtol 1e-10 with
LU; the converged discrete solution is unique, so P (virtual work) and p0 (max of the law pressure at the
gathered quadrature samples) must agree to far better than 1e-8 (the requirement).
"""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

from meshes.block import build_block_mesh

ROOT = Path(__file__).resolve().parents[1]
# the interpreter running the tests and the mpiexec beside it (the venv's), else the one on PATH: no venv path is
# assumed, so the file runs under any pytest start (``pytest``, ``python -m pytest``, another venv)
PYTHON = Path(sys.executable)
MPIEXEC = Path(shutil.which("mpiexec", path=str(PYTHON.parent)) or shutil.which("mpiexec") or "mpiexec")

SCRIPT = r'''
import json, sys
import dolfinx_solver  # noqa: F401
from dolfinx.io import gmsh as dgmsh
from mpi4py import MPI
from fem.obstacles import CircleObstacle
from fem.solver import solve_contact
md = dgmsh.read_from_msh(sys.argv[1], MPI.COMM_WORLD, 0, gdim=2)
res = solve_contact(md, CircleObstacle(center=(0.0, 10.0), radius=10.0), E=200e3, nu=0.3, traction="halfplane",
                    control="displacement", target=0.05, n_steps=2, symmetric_half=True)
if MPI.COMM_WORLD.rank == 0:
    print("RESULT " + json.dumps({"P": res.P, "p0": res.patches[0].p_max, "a": res.patches[0].half_width,
                                  "n": len(res.samples.s), "size": MPI.COMM_WORLD.size}))
'''


def _run(n, msh, script):
    env = dict(os.environ, PYTHONPATH=str(ROOT), OMP_NUM_THREADS="1")
    cmd = [str(PYTHON), str(script), str(msh)]
    if n > 1:
        cmd = [str(MPIEXEC), "-n", str(n), *cmd]
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=240, cwd=ROOT)
    assert out.returncode == 0, out.stderr[-2000:]
    line = [ln for ln in out.stdout.splitlines() if ln.startswith("RESULT ")][-1]
    return json.loads(line[len("RESULT "):])



def test_mpi_two_ranks_match_serial(tmp_path):
    a = 0.5
    mf = build_block_mesh(width=40 * a, height=40 * a, contact_half_width=a, h_contact=a / 10, half_model=True,
                          out_dir=tmp_path, name="mpi")
    script = tmp_path / "run_hertz.py"
    script.write_text(SCRIPT)
    serial = _run(1, mf.msh, script)
    parallel = _run(2, mf.msh, script)
    print(f"\nserial {serial}\nmpi-2  {parallel}")
    assert parallel["size"] == 2 and serial["n"] == parallel["n"]
    for key in ("P", "p0", "a"):
        assert abs(parallel[key] / serial[key] - 1.0) <= 1e-8, (key, serial[key], parallel[key])
