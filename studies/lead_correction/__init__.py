"""Lead correction: the helix correction that recentres a case's load from its FE pattern."""
