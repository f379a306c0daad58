"""Pictures: worlds and paths, replays and the experiment figures, drawn by matplotlib."""

__all__ = [
    "ablation_figure",
    "animate",
    "blit",
    "experiment_figures",
    "exploration_figure",
    "figure_parts",
    "formats",
    "goal_figure",
    "learning_curve_figures",
    "moment",
    "online_figure",
    "plot",
    "sweep_plot",
    "wall_threshold_figure",
    "window",
]
