"""Plan execution with every action checked from geometry (:mod:`.executor`), the executor's
belief of the cell (:mod:`.belief`), late-bound CRCL targets (:mod:`.targets`) and the records a
run leaves (:mod:`.records`)."""
