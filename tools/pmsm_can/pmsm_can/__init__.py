"""Watch and command the PMSM drive over CAN (python-can + cantools); the
protocol comes from tools/dbc/pmsm_drive.dbc."""
