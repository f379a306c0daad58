"""Controllers to measure TVL against: a Dynamic Window Approach and tabular Q-learning.

Both run on the same worlds, robot, sonar ring and seeds as TVL: the DWA knows the true
geometry, and the Q-learning learns over the single FAM's rules.
"""

__all__ = ["dwa", "dwa_kernel", "dwa_window", "qlearning", "qtable"]
