"""``python -m studies.analytic``: :func:`studies.analytic.driver.main`."""

import sys

from studies.analytic.driver import main

sys.exit(main())
