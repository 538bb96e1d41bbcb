"""What each quality control buys in error and costs in time; how well Estimate predicts."""
