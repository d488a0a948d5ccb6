"""`python -m flexbearing ARGS` = `flexbearing ARGS`."""
import sys

from flexbearing.cli.main import main

if __name__ == "__main__":
    sys.exit(main())
