"""The Dask render farm, its benchmark and its demo animation."""
