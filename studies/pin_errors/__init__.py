"""Pin position errors: how a planet's pin error changes the load sharing."""
