"""Stage 1, the scene: the YAML a user writes, validated into an immutable Scene (schema, files, overrides, rules)."""
