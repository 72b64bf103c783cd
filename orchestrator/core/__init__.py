"""Shared by every stage: errors, JSON and atomic file writes, number helpers. Imports no other stage."""
