"""``python -m studies.pin_errors``: :func:`studies.pin_errors.driver.main`."""

import sys

from studies.pin_errors.driver import main

sys.exit(main())
