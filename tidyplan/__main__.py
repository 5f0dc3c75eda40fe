"""``python -m tidyplan``: the command line.

Imports: tidyplan.cli.
"""

import sys

from tidyplan.cli.main import main

sys.exit(main())
