"""External codes: score their contact pressures against a case (``score.py``), export a case as a benchmark
(``export.py``, ``inp.py``), read CalculiX results (``frd.py``) and run CalculiX end to end (``ccx.py``).

The scorer needs no solve and never imports dolfinx (tests/test_external_score.py checks ``sys.modules``).
"""
