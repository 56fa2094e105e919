"""Scene definitions: ``cases/<name>.toml`` files and their typed loader."""

from cases.schema import CASE_DIR, Case, CaseError, Run, case_names, load_case

__all__ = ["CASE_DIR", "Case", "CaseError", "Run", "case_names", "load_case"]
