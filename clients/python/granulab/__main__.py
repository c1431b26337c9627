"""`python -m granulab ...`: the package's command line (granulab.cli)."""

import sys

from granulab.cli import main

sys.exit(main())
