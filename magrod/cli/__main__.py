"""python -m magrod.cli ..."""
import sys

from . import main

sys.exit(main())
