"""jobs/texture"""
