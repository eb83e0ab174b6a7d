"""The root-stress fillet-size study: the root stress against the read fillet's element size."""
