"""``python -m filmscale``: the command line."""

import sys

from filmscale.workflows.cli import main

sys.exit(main())
