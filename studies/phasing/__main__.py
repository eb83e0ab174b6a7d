"""``python -m studies.phasing``: :func:`studies.phasing.driver.main`."""

import sys

from studies.phasing.driver import main

sys.exit(main())
