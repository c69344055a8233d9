"""diagnosis/fit"""
