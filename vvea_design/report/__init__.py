"""Reports: HTML report, drawings, bill of materials."""
