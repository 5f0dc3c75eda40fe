"""Seeded WRS tidy-up rooms as scenario files (``tidyplan.generate.rooms``, whose docstring
says how they are drawn):

    python bench/wrs.py --layout one|two --out DIR [--rooms 20] [--first-seed 0]
                        [--wall-height 2.0] [--per-room 12] [--force]
"""

import sys

from tidyplan.generate.rooms import main

if __name__ == "__main__":
    sys.exit(main())
