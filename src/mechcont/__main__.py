"""``python -m mechcont``: the same command line as the ``mechcont`` script."""
from mechcont.cli import main

if __name__ == "__main__":
    main()
