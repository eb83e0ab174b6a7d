"""``python -m studies.fillet``: :func:`studies.fillet.driver.main`."""

import sys

from studies.fillet.driver import main

sys.exit(main())
