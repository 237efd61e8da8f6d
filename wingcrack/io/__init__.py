"""Writing results: summary.json, field files, pictures."""
