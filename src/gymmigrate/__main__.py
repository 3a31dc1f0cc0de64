"""Allow ``python -m gymmigrate``."""

from gymmigrate.cli import main

if __name__ == "__main__":
    main()
