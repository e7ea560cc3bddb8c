"""Controller of the biped stack: three-mass and LIPM models, linear MPC, estimator, IK."""
