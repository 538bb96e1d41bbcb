"""Panels that draw Whitted's settings."""
