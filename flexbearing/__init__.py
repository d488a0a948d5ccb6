"""flexbearing: a finite-element-centric flexible multibody simulator for aero-engine main-shaft
ball bearings with a flexible cage.

The package is a stack of layers, each importing only the ones below it (docs/architecture.md):

    physics core: common < mesh < fem_cage < multibody < coupling
    application:  simulation < analysis < studies < cli

`python -m flexbearing` runs the command line (flexbearing.cli.main). `flexbearing.verification`
holds the independent checks that tests and benchmarks run; the program never imports it.
"""
