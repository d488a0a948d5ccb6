"""`python -m flexbearing`: the `flexbearing` command (coupling.cli) run as a module. The library
is the packages common, mesh, fem_cage, multibody and coupling (docs/architecture.md)."""
