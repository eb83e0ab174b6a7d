"""The closed-form study: the analytical model's tables and figures against the paper's."""
