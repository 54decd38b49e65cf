"""Typer command line. Imports the other layers lazily inside commands."""
