"""magrod.integrability."""
