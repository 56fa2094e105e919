"""The studies' shape: no study imports another, reports and plots read JSON only, no study depends on the working
directory, every study has a typed config whose defaults are what it runs."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import grimp
import pytest

from workbench.cli import STUDIES
from workbench.paths import default_paths
from workbench.studies.bench_config import BenchConfig
from workbench.studies.concave_map_config import ConcaveMapConfig
from workbench.studies.convective_table_config import ConvectiveTableConfig
from workbench.studies.convergence_config import ConvergenceConfig
from workbench.studies.stability_config import StabilityConfig

STUDY_DIR = Path(__file__).resolve().parents[1] / "workbench" / "studies"
RUNNERS = {"workbench.studies.bench", "workbench.studies.convergence", "workbench.studies.stability",
           "workbench.studies.convective_table", "workbench.studies.validity", "workbench.studies.concave_map"}
# what each runner may import of the other study modules: its own config, specs, report and plot, the shared
# config and rates
OWN = {"workbench.studies.bench": {"workbench.studies.bench_config", "workbench.studies.bench_report",
                                   "workbench.studies.bench_plot", "workbench.studies.bench_two_body",
                                   "workbench.studies.bench_nested", "workbench.studies.bench_techniques",
                                   "workbench.studies.bench_startup", "workbench.studies.bench_measure",
                                   "workbench.studies.bench_accuracy", "workbench.studies.bench_scale",
                                   "workbench.studies.bench_process", "workbench.studies.bench_options",
                                   "workbench.studies.bench_log_events"},
       "workbench.studies.convergence": {"workbench.studies.convergence_config", "workbench.studies.convergence_report",
                                         "workbench.studies.convergence_plot"},
       "workbench.studies.stability": {"workbench.studies.stability_config", "workbench.studies.stability_specs",
                                       "workbench.studies.stability_report", "workbench.studies.stability_plot"},
       "workbench.studies.convective_table": {"workbench.studies.convective_table_config"},
       "workbench.studies.validity": {"workbench.studies.validity_config", "workbench.studies.validity_assemble",
                                      "workbench.studies.validity_report", "workbench.studies.validity_plot",
                                      "workbench.studies.validity_halfplanes",
                                      "workbench.studies.validity_elastic_wedge"},
       "workbench.studies.concave_map": {"workbench.studies.concave_map_config", "workbench.studies.concave_map_models",
                                         "workbench.studies.concave_map_report", "workbench.studies.concave_map_band",
                                         "workbench.studies.concave_map_interacting",
                                         "workbench.studies.concave_map_design"}}
# the shared pieces every study may import: config and rates, the point runner and its executor (local processes or
# mpi4py.futures ranks), the reference solve measured in the same run, the block scene's point helpers, and the
# time-and-where section every report ends with
SHARED = {"workbench.studies.config", "workbench.studies.rates", "workbench.studies.executor",
          "workbench.studies.reference", "workbench.studies.scene_point", "workbench.studies.where_report"}


@pytest.fixture(scope="module")
def graph():
    return grimp.build_graph("workbench", "fem", "meshes", "cases", "analytic")


def _studies_imported_by(graph, module: str) -> set[str]:
    return {m for m in graph.find_modules_directly_imported_by(module) if m.startswith("workbench.studies.")}


def test_the_cli_runs_every_study():
    assert set(STUDIES.values()) == RUNNERS


@pytest.mark.parametrize("study", sorted(RUNNERS))
def test_a_study_imports_no_other_study(graph, study):
    assert _studies_imported_by(graph, study) <= OWN[study] | SHARED


# a report's own section formatters (formatting only, no study code) and its study's config (read back from the JSON)
REPORT_OWN = {"bench_report": {"workbench.studies.bench_startup_report", "workbench.studies.bench_config",
                               "workbench.studies.bench_log_events"},
              "validity_report": {"workbench.studies.validity_config"},
              "stability_report": {"workbench.studies.stability_config"},
              "concave_map_report": {"workbench.studies.concave_map_models", "workbench.studies.concave_map_band",
                                     "workbench.studies.concave_map_rule"},
              "concave_map_rule": {"workbench.studies.concave_map_band"},
              "concave_map_models": {"workbench.studies.concave_map_config"}}
CONFIGS = ["bench_config", "convective_table_config", "convergence_config", "stability_config", "validity_config",
           "concave_map_config"]


@pytest.mark.parametrize("module", ["bench_report", "bench_startup_report", "bench_plot", "convergence_report",
                                    "convergence_plot", "stability_report", "stability_plot", "validity_report",
                                    "validity_plot", "concave_map_report", "concave_map_models", "concave_map_band",
                                    "concave_map_rule", "config", "bench_log_events",
                                    *CONFIGS, "rates", "executor", "reference",
                                    "scene_point", "where_report"])
def test_reports_plots_and_shared_modules_import_no_study(graph, module):
    """Reports and plots read the study JSON; the shared modules are leaves every study may import: none of them
    imports a study."""
    assert _studies_imported_by(graph, f"workbench.studies.{module}") <= SHARED | REPORT_OWN.get(module, set())


def test_no_study_path_is_relative_to_the_working_directory():
    """Output folders come from workbench.paths (``--out`` overrides): no ``Path("results...")`` literal."""
    for path in STUDY_DIR.glob("*.py"):
        text = path.read_text()
        assert 'Path("results' not in text and "Path('results" not in text, path.name


def test_default_folders_are_the_workbench_paths():
    paths = default_paths()
    assert ConvergenceConfig().out_dir == paths.study("convergence")
    assert StabilityConfig().out_dir == paths.study("stability")
    assert BenchConfig().out_dir == paths.study("bench")
    assert ConvectiveTableConfig().out_dir == paths.analytic
    assert ConcaveMapConfig().out_dir == paths.study("concave_map")
    assert StabilityConfig().cache_dir == BenchConfig().cache_dir == paths.mesh_cache
    assert ConvergenceConfig(out=Path("rel")).out_dir.is_absolute()


@pytest.mark.parametrize("cls", [ConvergenceConfig, StabilityConfig, BenchConfig, ConvectiveTableConfig,
                                 ConcaveMapConfig])
def test_configs_are_frozen(cls):
    cfg = cls()
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.out = Path("x")  # type: ignore[misc]


def test_convective_table_from_another_directory(tmp_path):
    """``workbench convective-table --out DIR`` run from an unrelated working directory writes only to DIR."""
    out = tmp_path / "ct"
    proc = subprocess.run([sys.executable, "-m", "workbench", "convective-table", "--out", str(out)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert sorted(p.name for p in out.iterdir()) == [".workbench-owned", "convective.json", "convective.md"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ct"]
