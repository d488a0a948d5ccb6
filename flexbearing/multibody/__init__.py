"""Bearing multibody core: split-inner-ring geometry, contact and lubrication models,
rigid bodies, the quasi-static solver and the time integrator. Does not import the FE stack."""
