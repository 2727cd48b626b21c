"""python -m magrod.cli ..."""
from . import console_main

console_main()
