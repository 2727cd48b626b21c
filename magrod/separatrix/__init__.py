"""magrod.separatrix."""
