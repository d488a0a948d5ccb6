"""Example scenes (TOML), installed with the package as flexbearing.scenes: `flexbearing demo` runs
the four paper_* ones. Read them as files (importlib.resources.files("flexbearing.scenes")).
"""
