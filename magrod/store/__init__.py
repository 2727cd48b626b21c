"""The store wing: chaos maps on disk and on a Dask cluster, kept apart from the mathematics.

  tiles.py      the resumable zarr store of a map: layout, identity, content hashes, markers, the tiles and
                refinement rounds run on Dask and verified as they arrive
  cluster.py    the Dask cluster's lifecycle: a LocalCluster started and stopped, a running scheduler reached
                and checked (TLS refused without certificates), the machine's limits checked first
  resumable.py  a whole stored map, `stored_map(spec, out)`, with the policy `magrod chaosmap` had; and the
                public `chaos_map(..., store=DIR)`

The wing imports the numerics (magrod.chaos.maps, .indicators, .refine) and core; nothing in the numerics
imports it."""
