"""Every test may load a case: the scenes register their case schemas (cases.schema.SceneSchema) on import."""

import workbench.scenes  # noqa: F401
