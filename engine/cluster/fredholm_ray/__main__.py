"""`python -m fredholm_ray` runs the fredholm-ray command."""
import sys

from .cli import main

sys.exit(main())
