"""The pressure plot draws and lists only curves that exist: a two-body run's samples have no stress-based pressure
(sigma_nn all NaN), so its legend has no "FEM -sigma_nn"; a block run's has."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.reports import plots


def _legend(monkeypatch, tmp_path, sigma_nn, predictions):
    figs = []
    monkeypatch.setattr(plots, "save_figure", lambda fig, path, **kw: figs.append(fig))
    x = np.linspace(-1.0, 1.0, 11)
    p = np.clip(1.0 - x**2, 0.0, None)
    panel = {"label": "run", "x": x, "p_fem": p, "sigma_nn": sigma_nn, "xlabel": "x (mm)", "xlim": (-1.0, 1.0),
             "predictions": {k: (x, v(p)) for k, v in predictions.items()}}
    plots.plot_pressure_panels([panel], tmp_path / "p.png", title="t")
    (fig,) = figs
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    residual = fig.axes[1].get_ylabel()
    plots.plt.close(fig)
    return labels, residual


def test_no_stress_curve_without_stresses(monkeypatch, tmp_path):
    labels, residual = _legend(monkeypatch, tmp_path, np.full(11, np.nan),
                               {"missing": lambda p: np.full_like(p, np.nan), "exact circle": lambda p: p})
    assert labels == ["FEM (contact law)", "exact circle"]
    assert "exact circle" in residual  # the residual is taken against a curve that exists


@pytest.mark.parametrize("sigma_nn", [np.linspace(0.0, 1.0, 11), np.r_[np.nan, np.linspace(0.0, 1.0, 10)]])
def test_stress_curve_with_stresses(monkeypatch, tmp_path, sigma_nn):
    labels, _ = _legend(monkeypatch, tmp_path, sigma_nn, {"Hertz": lambda p: p})
    assert labels == ["FEM (contact law)", r"FEM $-\sigma_{nn}$", "Hertz"]


def test_has_curve():
    assert not plots.has_curve(None) and not plots.has_curve([]) and not plots.has_curve([np.nan, np.inf])
    assert plots.has_curve([np.nan, 0.0])
