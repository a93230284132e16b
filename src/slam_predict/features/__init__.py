"""Floor-plan features (seed thesis ch. 5): rooms and geometry, topological graph, Voronoi graph
and Voronoi traversal. Entry point: :func:`slam_predict.features.vector.compute_features`;
algorithms and deviations from the thesis: docs/features.md."""
