"""magrod.chaos."""
