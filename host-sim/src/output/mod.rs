//! Files written by a run: the time series (CSV), the plots (PNG) and the summary (JSON).
