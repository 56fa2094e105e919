"""Load and fault campaign (``make faults``, issue 15): concurrent runs, signals during writes, a full disk.

Usage: ``python tests/fault_campaign.py [--out results/faults] [--quick]``. Writes ``<out>/faults.json`` and
``<out>/report.md``; exits 1 unless 0 corrupted files, 0 lost previous results and 0 unnamed failures.

Scenarios (every run is the real CLI, ``workbench run CASE --ci``, in its own process, OMP_NUM_THREADS = 1):

1. **load**: 20 runs at once on the 2 cores, 8 x ``hertz_cylinder``, 6 x ``wedge``, 6 x
   ``hertz_augmented_lagrangian``, all into one output folder (one mesh cache). Each must exit 0, and the final
   folders must be complete and parse.
2. **signals**: a baseline result, then runs interrupted by SIGINT or SIGTERM (some twice in a row) at times
   spread over the run, the write phase included. An interrupted run must exit 130 (or 0 if it finished first) and
   leave the previous result byte-identical (or, if it finished, a complete new one).
3. **full disk**: the output folder on a small tmpfs (or, if none can be mounted, ENOSPC simulated in the
   atomic writer); a baseline result, then the free space cut to several sizes and the case rerun. Each rerun must
   exit 1 with a named ``No space left on device`` line (or 0 if it fit), and the previous result must stay
   byte-identical.
4. **Newton signals** (issue 23): a baseline result, then ``wedge --h-contact 0.001`` interrupted by SIGINT or
   SIGTERM right after a Newton progress line (inside the next load step's SNES solve, which used to give a PETSc
   traceback and exit 1). Each must exit 130 / 143 with one ``interrupted: ... during the Newton solve`` line, the
   previous result byte-identical, no staging folder left.
5. **SIGKILL** (issue 23): runs killed with SIGKILL at times spread over the run (nothing can clean up then);
   the staging folders they leave are counted, then the next run must clear them (``stale``: any left after the
   next run) and leave a complete result (``lost`` otherwise).
6. **score and export signals** (issue 35): a baseline ``score`` (three Hertz levels) and ``export --format inp``,
   then each rerun interrupted by SIGINT or SIGTERM (some twice in a row) at times spread over the run, the write
   and the exit included; and each interrupted at every named moment of its end (``WORKBENCH_TEST_SIGNAL_AT``: the
   swap, after the work, the exit, the atexit handlers, just before ``os._exit``). Each must exit 130 / 143 (or 0
   if it finished first) with one line, and leave the previous folder byte-identical or a complete new one.
7. **score and export collisions** (issue 35): 4 ``score``, 4 ``export`` (json and inp) and 2 ``run`` at once into
   one output folder (one mesh cache, one score and one export folder): each must exit 0 and the final folders be
   complete.

Counted: corrupted files (a JSON that does not parse, an empty or headless CSV, a truncated result folder),
lost previous results (a folder that is neither the previous one byte for byte nor a complete new one), unnamed
failures (a non-zero exit without a one-line ``error:`` message, or a traceback), and leftovers (staging
folders and temporary files; reported, not counted as corruption).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from signal_support import interrupt_at

ROOT = Path(__file__).resolve().parents[1]
WB = [sys.executable, "-m", "workbench"]
ENV = os.environ | {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
REQUIRED = ("metrics.json", "series.json", "pressure.csv", "report.md", "run.log", "mesh.json")


def snapshot(folder: Path) -> dict[str, str]:
    out = {}
    if not folder.exists():
        return out
    for p in sorted(folder.rglob("*")):
        if p.is_file():
            out[str(p.relative_to(folder))] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


def corrupted(folder: Path) -> list[str]:
    """Files of a result folder that are missing, empty or do not parse."""
    bad = [f"{folder.name}/{f} missing" for f in REQUIRED if not (folder / f).is_file()]
    for p in folder.rglob("*"):
        if not p.is_file():
            continue
        rel = f"{folder.name}/{p.relative_to(folder)}"
        if p.stat().st_size == 0:
            bad.append(f"{rel} empty")
        elif p.suffix == ".json":
            try:
                json.loads(p.read_text())
            except ValueError:
                bad.append(f"{rel} does not parse")
        elif p.suffix == ".csv" and "," not in p.read_text().splitlines()[0]:
            bad.append(f"{rel} has no header")
    return bad


def leftovers(out: Path) -> list[str]:
    return [str(p.relative_to(out)) for p in out.rglob(".*") if ".staging." in p.name or ".old." in p.name
            or p.name.endswith(".tmp")]


def named(code: int, err: str) -> bool:
    """A failure is named: one ``error:`` line (or the interruption line), no traceback."""
    if code == 0:
        return True
    lines = [ln for ln in err.splitlines() if ln.startswith(("error:", "interrupted:"))]
    return bool(lines) and "Traceback" not in err


def run(case: str, out: Path, **kw) -> subprocess.Popen:
    return subprocess.Popen([*WB, "run", case, "--ci", "--out", str(out)], cwd=ROOT, env=ENV,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, **kw)


def scenario_load(out: Path, n: int) -> dict:
    cases = (["hertz_cylinder"] * 8 + ["wedge"] * 6 + ["hertz_augmented_lagrangian"] * 6)[:n]
    t0 = time.perf_counter()
    procs = [(c, run(c, out)) for c in cases]
    results = [(c, p.wait(timeout=1800), p.stderr.read()) for c, p in procs]
    bad = [f"{c}: exit {code}: {err.strip().splitlines()[-1] if err.strip() else ''}" for c, code, err in results
           if code != 0]
    corrupt = [b for c in sorted(set(cases)) for b in corrupted(out / c)]
    return {"runs": len(cases), "wall_s": round(time.perf_counter() - t0, 1), "exit_nonzero": bad,
            "unnamed": [c for c, code, err in results if not named(code, err)], "corrupted": corrupt, "lost": [],
            "leftovers": leftovers(out)}


def scenario_signals(out: Path, n: int, seed: int = 15) -> dict:
    rng = random.Random(seed)
    case = "hertz_cylinder"
    p = run(case, out)
    assert p.wait(timeout=900) == 0, p.stderr.read()
    t0 = time.perf_counter()
    p = run(case, out)
    p.wait(timeout=900)
    duration = time.perf_counter() - t0
    events, corrupt, lost, unnamed = [], [], [], []
    for i in range(n):
        before = snapshot(out / case)
        sig = [signal.SIGINT, signal.SIGTERM][i % 2]
        delay = rng.uniform(0.3, 1.05) * duration  # the last part of the run is the write phase
        p = run(case, out)
        time.sleep(delay)
        sent = []
        for _ in range(1 + (i % 3 == 2)):  # every third: the signal twice in a row
            if p.poll() is None:
                p.send_signal(sig)
                sent.append(sig.name)
                time.sleep(0.05)
        code = p.wait(timeout=900)
        err = p.stderr.read()
        after = snapshot(out / case)
        if code == 0:
            state = "finished (new complete result)"
            corrupt += corrupted(out / case)
        elif after == before:
            state = "previous result byte-identical"
        elif not corrupted(out / case):
            state = "new complete result (the signal came after the swap)"
        else:
            state = "CHANGED"
            lost.append(f"{case} after {sent} at {delay:.2f} s")
        if code not in (0, 130, 143) or not named(code, err):
            unnamed.append(f"{sent} at {delay:.2f} s: exit {code}: {err.strip()[-300:]}")
        events.append({"signals": sent, "at_s": round(delay, 2), "exit": code, "state": state})
    return {"runs": n, "run_duration_s": round(duration, 2), "events": events, "corrupted": corrupt, "lost": lost,
            "unnamed": unnamed, "leftovers": leftovers(out)}


def _interrupt_after(argv: list[str], when: str, sig: int, extra: float) -> tuple[int, str, float]:
    """Run the CLI, send ``sig`` ``extra`` s after the first stdout line containing ``when``."""
    code, err, secs = interrupt_at(argv, when=when, sig=sig, delay=extra, cwd=ROOT, env=ENV, timeout=math.inf,
                                   wait=900)
    return code, err, float("nan") if secs is None else secs


def scenario_newton_signals(out: Path, n: int, seed: int = 23) -> dict:
    rng = random.Random(seed)
    case = "wedge"
    p = run(case, out)
    assert p.wait(timeout=900) == 0, p.stderr.read()
    events, corrupt, lost, unnamed = [], [], [], []
    for i in range(n):
        before = snapshot(out / case)
        sig = [signal.SIGINT, signal.SIGTERM][i % 2]
        when = ["[theta=pi/20] first:", "[theta=pi/20] step:", "[theta=pi/5] first:"][i % 3]
        extra = round(rng.uniform(0.0, 0.5), 2)
        code, err, latency = _interrupt_after(["run", case, "--h-contact", "0.001", "--out", str(out)], when, sig,
                                              extra)
        line = (err.strip().splitlines() or [""])[-1]
        inside = "during the Newton solve" in line
        if snapshot(out / case) != before:
            lost.append(f"{case} after {sig.name} at '{when}' + {extra} s")
        if code != 128 + sig or not named(code, err) or len(err.strip().splitlines()) != 1:
            unnamed.append(f"{sig.name} at '{when}' + {extra} s: exit {code}: {err.strip()[-300:]}")
        events.append({"signal": sig.name, "after": when, "plus_s": extra, "exit": code,
                       "in_newton": inside, "latency_s": round(latency, 2), "line": line[:90]})
    return {"runs": n, "events": events, "corrupted": corrupt, "lost": lost, "unnamed": unnamed,
            "stale": [], "leftovers": leftovers(out)}


def scenario_sigkill(out: Path, n: int, seed: int = 9) -> dict:
    rng = random.Random(seed)
    case = "hertz_cylinder"
    p = run(case, out)
    assert p.wait(timeout=900) == 0, p.stderr.read()
    t0 = time.perf_counter()
    p = subprocess.Popen([*WB, "run", case, "--h-contact", "0.002", "--out", str(out)], cwd=ROOT, env=ENV,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    p.wait(timeout=900)
    duration = time.perf_counter() - t0
    events, corrupt, lost, unnamed, stale = [], [], [], [], []
    for _ in range(n):
        # a fresh mesh size each time, so the kill can land in gmsh too
        h = round(rng.uniform(0.0015, 0.003), 5)
        delay = round(rng.uniform(0.2, 1.0) * duration, 2)
        p = subprocess.Popen([*WB, "run", case, "--h-contact", str(h), "--out", str(out)], cwd=ROOT, env=ENV,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(delay)
        killed = p.poll() is None
        p.kill()
        p.wait(timeout=60)
        left = leftovers(out)
        nxt = run(case, out)
        code = nxt.wait(timeout=900)
        err = nxt.stderr.read()
        after = leftovers(out)
        if code != 0 or not named(code, err):
            unnamed.append(f"next run after SIGKILL at {delay} s: exit {code}: {err.strip()[-300:]}")
        bad = corrupted(out / case)
        if bad:
            lost.append(f"{case} after SIGKILL at {delay} s + next run: {bad}")
        stale += after
        events.append({"h_contact": h, "kill_at_s": delay, "killed_mid_run": killed, "left_by_kill": len(left),
                       "next_run_exit": code, "left_after_next_run": len(after)})
    return {"runs": n, "run_duration_s": round(duration, 2), "events": events, "corrupted": corrupt, "lost": lost,
            "unnamed": unnamed, "stale": stale, "leftovers": leftovers(out)}


def _levels(folder: Path) -> list[str]:
    """Three Hertz levels of hertz_cylinder (a = 0.5 mm) as csv, h = 0.04, 0.02, 0.01 mm."""
    import numpy as np

    sys.path.insert(0, str(ROOT))
    from analytic import hertz as hz
    from analytic import materials

    folder.mkdir(parents=True, exist_ok=True)
    E_star = materials.plane_strain_modulus(210000.0, 0.3)
    P = hz.hertz_load_from_half_width(0.5, 10.0, E_star)
    p0 = hz.hertz(P, 10.0, E_star).p0
    files = []
    for h in (0.04, 0.02, 0.01):
        x = np.arange(-int(round(0.8 / h)), int(round(0.8 / h)) + 1) * h
        p = p0 * (0.995 - 5 * h**2) * np.sqrt(np.clip(1 - (x / 0.5) ** 2, 0, None))
        f = folder / f"level_{h}.csv"
        f.write_text("x_mm,p_MPa,P_N_per_mm\n" + "".join(f"{a!r},{b!r},{P!r}\n" for a, b in zip(x.tolist(), p.tolist(),
                                                                                           strict=True)))
        files.append(str(f))
    return files


def _external(kind: str, out: Path, levels: list[str], fmt: str = "inp") -> list[str]:
    if kind == "score":
        return [*WB, "score", "hertz_cylinder", *levels, "--out", str(out)]
    return [*WB, "export", "hertz_cylinder", "--format", fmt, "--out", str(out)]


def corrupted_external(folder: Path) -> list[str]:
    """Files of a score or export folder that are missing, empty or do not parse."""
    if not folder.exists():
        return []
    need = ("score.json", "report.md", "report.html", "pressure.png") if folder.name.startswith("score_") else ()
    bad = [f"{folder.name}/{f} missing" for f in need if not (folder / f).is_file()]
    # an export has one folder per level (issue 36): every file below the folder
    files = [p for p in folder.rglob("*") if p.is_file() and p.name != ".workbench-owned"]
    if not files:
        bad.append(f"{folder.name}: no file")
    for p in files:
        name = p.relative_to(folder)
        if p.stat().st_size == 0:
            bad.append(f"{folder.name}/{name} empty")
        elif p.suffix == ".json":
            try:
                json.loads(p.read_text())
            except ValueError:
                bad.append(f"{folder.name}/{name} does not parse")
    return bad


def scenario_external_signals(out: Path, n: int, seed: int = 35) -> dict:
    rng = random.Random(seed)
    levels = _levels(out.parent / "levels")
    events, corrupt, lost, unnamed = [], [], [], []
    durations = {}
    for kind in ("score", "export"):
        for _ in range(2):  # the second is timed (the mesh cache is warm)
            t0 = time.perf_counter()
            proc = subprocess.run(_external(kind, out, levels), cwd=ROOT, env=ENV, capture_output=True, text=True,
                                  timeout=900)
            assert proc.returncode == 0, proc.stderr
            durations[kind] = time.perf_counter() - t0
    folders = {"score": out / "score_hertz_cylinder", "export": out / "export_hertz_cylinder"}
    points = ["swap", "work-done", "exit", "atexit", "os-exit"]
    plan = ([("time", i, ["score", "export"][i % 2]) for i in range(n)]
            + [("point", pt, kind) for pt in points for kind in ("score", "export")])
    for i, (how, what, kind) in enumerate(plan):
        sig = [signal.SIGINT, signal.SIGTERM][(i // 2) % 2]
        folder = folders[kind]
        before = snapshot(folder)
        env = ENV
        if how == "point":
            env = ENV | {"WORKBENCH_TEST_SIGNAL_AT": f"{what}:{sig.name}"}
        p = subprocess.Popen(_external(kind, out, levels), cwd=ROOT, env=env, stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE, text=True)
        sent, at = [], None
        if how == "time":
            at = rng.uniform(0.2, 1.1) * durations[kind]
            time.sleep(at)
            for _ in range(1 + (what % 3 == 2)):  # every third: the signal twice in a row
                if p.poll() is None:
                    p.send_signal(sig)
                    sent.append(sig.name)
                    time.sleep(0.05)
        else:
            sent.append(f"{sig.name} at {what}")
        code = p.wait(timeout=900)
        err = p.stderr.read()
        after = snapshot(folder)
        if code == 0:
            state = "finished (new complete result)"
            corrupt += corrupted_external(folder)
        elif after == before:
            state = "previous result byte-identical"
        elif not corrupted_external(folder):
            state = "new complete result (the signal came after the swap)"
        else:
            state = "CHANGED"
            lost.append(f"{folder.name} after {sent}")
        lines = err.strip().splitlines()
        if code not in (0, 130, 143) or not named(code, err) or (code != 0 and len(lines) != 1) or \
                (how == "point" and code != 128 + sig):
            unnamed.append(f"{kind} {sent} at {at}: exit {code}: {err.strip()[-300:]}")
        events.append({"command": kind, "signals": sent, "at_s": None if at is None else round(at, 2), "exit": code,
                       "state": state, "line": (lines[-1] if lines else "")[:90]})
    return {"runs": len(plan), "duration_s": {k: round(v, 2) for k, v in durations.items()}, "events": events,
            "corrupted": corrupt, "lost": lost, "unnamed": unnamed, "leftovers": leftovers(out)}


def scenario_external_collisions(out: Path) -> dict:
    levels = _levels(out.parent / "levels_c")
    cmds = ([("score", _external("score", out, levels))] * 4 + [("export json", _external("export", out, levels,
                                                                                          "json"))] * 2
            + [("export inp", _external("export", out, levels, "inp"))] * 2
            + [("run", [*WB, "run", "hertz_cylinder", "--ci", "--no-pictures", "--out", str(out)])] * 2)
    t0 = time.perf_counter()
    procs = [(k, subprocess.Popen(c, cwd=ROOT, env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True))
             for k, c in cmds]
    results = [(k, p.wait(timeout=1800), p.stderr.read()) for k, p in procs]
    bad = [f"{k}: exit {code}: {err.strip().splitlines()[-1] if err.strip() else ''}" for k, code, err in results
           if code != 0]
    corrupt = (corrupted_external(out / "score_hertz_cylinder") + corrupted_external(out / "export_hertz_cylinder")
               + corrupted(out / "hertz_cylinder"))
    return {"runs": len(cmds), "wall_s": round(time.perf_counter() - t0, 1), "exit_nonzero": bad,
            "unnamed": [k for k, code, err in results if not named(code, err)] + bad, "corrupted": corrupt,
            "lost": [], "leftovers": leftovers(out)}


def _mount_tmpfs(path: Path, size: str) -> bool:
    path.mkdir(parents=True, exist_ok=True)
    return subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(path)],
                          capture_output=True).returncode == 0


def scenario_full_disk(work: Path, free_kb: list[int]) -> dict:
    case = "hertz_cylinder"
    disk = work / "disk"
    real = _mount_tmpfs(disk, "64m")
    out = disk / "results"
    events, corrupt, lost, unnamed = [], [], [], []
    try:
        p = run(case, out)
        assert p.wait(timeout=900) == 0, p.stderr.read()
        for kb in free_kb:
            before = snapshot(out / case)
            filler = disk / "filler"
            env = None
            if real:
                st = os.statvfs(disk)
                free = st.f_bavail * st.f_frsize
                with open(filler, "wb") as fh:
                    fh.write(b"\0" * max(free - kb * 1024, 0))
            else:  # simulated: the atomic writer raises ENOSPC once `kb` kB have been written
                env = ENV | {"WORKBENCH_FAULT_ENOSPC_AFTER_KB": str(kb)}
            cmd = [*WB, "run", case, "--ci", "--out", str(out)]
            if not real:
                cmd = [sys.executable, str(Path(__file__).resolve()), "--simulate-enospc", "--", *cmd[1:]]
            proc = subprocess.run(cmd, cwd=ROOT, env=env or ENV, capture_output=True, text=True, timeout=900)
            filler.unlink(missing_ok=True)
            after = snapshot(out / case)
            if proc.returncode == 0:
                state = "fitted (new complete result)"
                corrupt += corrupted(out / case)
            elif after == before:
                state = "previous result byte-identical"
            else:
                state = "CHANGED"
                lost.append(f"{case} with {kb} kB free")
            msg = next((ln for ln in proc.stderr.splitlines() if ln.startswith("error:")), "")
            if proc.returncode not in (0, 1) or not named(proc.returncode, proc.stderr):
                unnamed.append(f"{kb} kB: exit {proc.returncode}: {proc.stderr.strip()[-300:]}")
            events.append({"free_kB": kb, "exit": proc.returncode, "state": state, "message": msg[:200]})
        left = leftovers(out)
    finally:
        if real:
            subprocess.run(["umount", str(disk)], capture_output=True)
    return {"mode": "tmpfs 64 MB, filled to the free space given" if real else "simulated ENOSPC (no tmpfs)",
            "events": events, "corrupted": corrupt, "lost": lost, "unnamed": unnamed, "leftovers": left}


def simulate_enospc(argv: list[str]) -> int:
    """Run the workbench with the atomic writer failing with ENOSPC after ``$WORKBENCH_FAULT_ENOSPC_AFTER_KB``."""
    import errno

    import workbench.atomic as atomic

    budget = [int(os.environ["WORKBENCH_FAULT_ENOSPC_AFTER_KB"]) * 1024]
    real_write_text = atomic.write_text

    def write_text(path, text):
        budget[0] -= len(text.encode())
        if budget[0] < 0:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        real_write_text(path, text)

    atomic.write_text = write_text
    from workbench.cli import main

    return main(argv)


def report(res: dict) -> str:
    tot = {k: sum(len(s.get(k, [])) for s in res["scenarios"].values())
           for k in ("corrupted", "lost", "unnamed", "stale")}
    lines = ["# Load and fault campaign", "",
             f"**{tot['corrupted']} corrupted files, {tot['lost']} lost previous results, {tot['unnamed']} unnamed "
             f"failures or tracebacks, {tot['stale']} stale staging folders after the next run** "
             f"({res['wall_s']:.0f} s on {os.cpu_count()} cores).", ""]
    for name, s in res["scenarios"].items():
        lines += [f"## {name}", ""]
        for k, v in s.items():
            if k == "events":
                continue
            lines.append(f"- {k}: {v if not isinstance(v, list) else (len(v) if not v else v)}")
        if s.get("events"):
            keys = list(s["events"][0])
            lines += ["", "| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
            lines += ["| " + " | ".join(str(e[k]) for k in keys) + " |" for e in s["events"]]
        lines.append("")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv and argv[0] == "--simulate-enospc":
        return simulate_enospc(argv[2:] if argv[1:2] == ["--"] else argv[1:])
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "results" / "faults")
    ap.add_argument("--quick", action="store_true", help="fewer runs (development)")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    work = Path(tempfile.mkdtemp(prefix="faults_"))
    try:
        scen = {
            "load: 20 concurrent runs": scenario_load(work / "load", 6 if args.quick else 20),
            "signals: SIGINT/SIGTERM during runs and writes": scenario_signals(work / "signals",
                                                                             4 if args.quick else 12),
            "full disk": scenario_full_disk(work, [16, 64, 256, 1024] if args.quick else
                                            [4, 16, 64, 128, 256, 512, 1024, 2048]),
            "Newton signals: SIGINT/SIGTERM inside the SNES solve": scenario_newton_signals(
                work / "newton", 2 if args.quick else 6),
            "SIGKILL mid-run: staging cleared by the next run": scenario_sigkill(work / "sigkill",
                                                                                2 if args.quick else 6),
            "score and export: SIGINT/SIGTERM during their runs, writes and exit": scenario_external_signals(
                work / "external" / "out", 4 if args.quick else 12),
            "score, export and run at once into one folder": scenario_external_collisions(work / "collide" / "out"),
        }
    finally:
        shutil.rmtree(work, ignore_errors=True)
    res = {"wall_s": time.perf_counter() - t0, "scenarios": scen}
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "faults.json").write_text(json.dumps(res, indent=2) + "\n")
    text = report(res)
    (args.out / "report.md").write_text(text)
    print(text.splitlines()[2])
    print(f"-> {args.out / 'report.md'}")
    bad = sum(len(s.get(k, [])) for s in scen.values() for k in ("corrupted", "lost", "unnamed", "stale"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
