"""jobs/analyse"""
