"""Property-based fuzz tests (hypothesis): the project's own error or a finite result."""
