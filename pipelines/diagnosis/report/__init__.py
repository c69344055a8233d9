"""diagnosis/report"""
