"""diagnosis/verdict"""
