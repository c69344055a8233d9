"""diagnosis/surface"""
