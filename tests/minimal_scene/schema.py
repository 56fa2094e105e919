"""Case schema of the minimal scene ``flat_block`` (what its case files may say): a
:class:`cases.schema.SceneSchema` with the scene's geometry record."""

from __future__ import annotations

from dataclasses import dataclass

from cases.schema import Geometry, SceneSchema

__all__ = ["FLAT_BLOCK_SCHEMA", "FlatBlockGeometry"]


@dataclass(frozen=True)
class FlatBlockGeometry(Geometry):
    """A block under a rigid flat plane (test scene).

    Attributes:
        width: The block's width W (mm); the model is its half x >= 0.
        height: The block's height H (mm).
    """

    width: float = 2.0
    height: float = 1.0


FLAT_BLOCK_SCHEMA = SceneSchema(
    name="flat_block", geometry=FlatBlockGeometry,
    indenters={"plane": frozenset({"width", "height"})},
    predictions={"plane": ("uniform",)},
    controls=("displacement",),
    ranges={"width": (0.0, 1e3, False, True, "0 < width <= 1000 mm"),
            "height": (0.0, 1e3, False, True, "0 < height <= 1000 mm")},
    tolerances={"uniformity": "largest |p / p_exact - 1| over the contact samples",
                "load": "|P / P_exact - 1|"},
    budget_widths="the block is the real geometry (no error budget)")
