"""`/usr/bin/python3 -m ProgSurf build ...`: see ProgSurf.cli."""
import sys

from ProgSurf.cli import main

sys.exit(main())
