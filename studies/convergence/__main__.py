"""``python -m studies.convergence``: :func:`studies.convergence.driver.main`."""

import sys

from studies.convergence.driver import main

sys.exit(main())
