"""The CalculiX peer check: the same one-branch scene solved by ccx beside our solver."""
