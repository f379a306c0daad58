"""Worlds to and from other map formats (occupancy grids), as pure conversions."""

__all__ = ["cells", "free_space", "grid_world", "raster", "resample", "text_grid"]
