"""Karto graph SLAM as slam_toolbox's ``lib/karto_sdk`` runs it in mapping mode (docs/karto.md)."""
