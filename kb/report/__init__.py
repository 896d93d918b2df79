"""The visual report of a run or a campaign: one self-contained HTML page (plotly)."""
