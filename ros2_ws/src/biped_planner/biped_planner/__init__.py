"""Dynamic planner of the biped stack: state machine, A*, footsteps, step timing, references."""
