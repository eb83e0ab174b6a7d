"""The planet phasing study (Parker 2000): the net force on the sun over the mesh cycle from the
FE."""
