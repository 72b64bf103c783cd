"""`python -m orchestrator.cli`: the `debrisfoam` command without the installed script."""

import sys

from orchestrator.cli import main

sys.exit(main())
