"""jobs/combine"""
