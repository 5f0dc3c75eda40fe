"""The execution monitor (Yamazaki et al.): behaviour units and layered recovery."""
