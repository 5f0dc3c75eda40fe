"""Seeded tidy-up problems for domains/tidy.pddl and their exact optimum
(``tidyplan.generate.tasks``, whose docstring says how they are built)."""

import sys

from tidyplan.generate.tasks import main

if __name__ == "__main__":
    sys.exit(main())
