"""Worlds to and from other map formats (occupancy grids), as pure conversions."""
