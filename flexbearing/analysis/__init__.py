"""What a finished run means: windows per phase and impact, the cage's motion, dynamic
amplification, plots, the von Mises picture and field export for ParaView, export to
netCDF/CSV, and the report (Markdown + one HTML page). Reads results files; runs nothing."""
