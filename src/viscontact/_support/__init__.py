"""Plumbing shared by every layer, knowing no physics (imports nothing else of viscontact but
its version): the progress reporter (:mod:`.progress`), output files and directories written
safely and stamped with the command that wrote them (:mod:`.outputs`), a forked parallel
map (:mod:`.parallel`) and a lock shared by processes (:mod:`.locks`)."""
