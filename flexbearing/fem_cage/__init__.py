"""dolfinx + SLEPc: the cage's stiffness and mass, free–free modes, Craig–Bampton reduction,
modal stress shapes, von Mises recovery and the reduced-cage file.

Only the modules that build these import dolfinx; `flexbearing.fem_cage.reduced_cage` (reading the file)
and the von Mises evaluator do not, so a run with a cached reduced cage never loads the FE stack.
"""
