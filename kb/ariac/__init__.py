"""NIST ARIAC's kitting trials in kitkb (issue 32)."""
