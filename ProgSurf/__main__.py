"""`/usr/bin/python3 -m ProgSurf build ...`: see ProgSurf.cli."""
import os
import sys

# small matrices: BLAS threads only add overhead (see benchmarks/run.py); before numpy is imported
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from ProgSurf.cli import main  # noqa: E402

sys.exit(main())
