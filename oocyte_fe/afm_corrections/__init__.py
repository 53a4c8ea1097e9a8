"""The project's FE runs behind ``afm.corrections``: the shelled-oocyte table
(:mod:`~oocyte_fe.afm_corrections.table`) and the check of Dimitriadis' bonded-layer
correction in its own limit (:mod:`~oocyte_fe.afm_corrections.bottom_check`). Kept outside
``oocyte_fe.experiment`` so that the FE results they cache stay valid while they change."""
