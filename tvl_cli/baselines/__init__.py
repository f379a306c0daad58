"""Controllers to measure TVL against, on the same worlds, robot, sonar ring and seeds:
a Dynamic Window Approach that knows the true geometry, and tabular Q-learning over the
single FAM's rules."""
