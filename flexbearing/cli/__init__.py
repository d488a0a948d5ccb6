"""The `flexbearing` command: `main` holds the parser, each other module one sub-command that only
parses its arguments, calls library functions and prints."""
