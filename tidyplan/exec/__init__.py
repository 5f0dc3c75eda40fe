"""Bindings of symbolic actions to behaviour units, and the worlds that run them."""
