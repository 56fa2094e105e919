"""``python -m workbench`` is the same as the console command ``workbench``."""

import sys

from workbench.cli import main

sys.exit(main())
