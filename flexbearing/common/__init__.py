"""What every layer may import: input validation (InputError, require_range), materials, the cache.

The bottom of the package stack (docs/architecture.md): common < mesh < fem_cage < multibody <
coupling. Nothing here imports another flexbearing package, numpy or the FE stack.
"""
