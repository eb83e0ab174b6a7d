"""Closed-form models of the references: singh2007 single and double pinion moments,
pust2016 radial mesh stiffness, parker2000 planet phasing."""
