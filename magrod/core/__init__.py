"""magrod.core."""
