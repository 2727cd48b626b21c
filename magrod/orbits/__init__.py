"""magrod.orbits."""
