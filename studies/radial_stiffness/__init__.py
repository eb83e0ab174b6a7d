"""The radial stiffness of an external gear mesh (Pust 2016) from the FE."""
