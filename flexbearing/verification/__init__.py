"""Independent checks that only tests and benchmarks use (never imported by the program): the
CalculiX comparison of the cage's stress and frequencies, the frequency response of the reduced
cage against the full model, and the stress-convergence study."""
