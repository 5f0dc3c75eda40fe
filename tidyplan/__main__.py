import sys

from tidyplan.cli.main import main

sys.exit(main())
