"""The contact stage: debris contact as geometry and event files, shared by both ways of carrying
debris (the coupled runner in orchestrator.run, the one-way transport in orchestrator.transport).

It owns the oriented-box geometry (`boxes`), a scene's obstacles and the contacts between bodies
and obstacles (`geometry`), resolving a contact as an impact (`resolution`), the contact knobs of
the runner (`settings`), and a case's contact-event files: contacts.json, the runner's
impact_events.csv and each impact's pulse under contacts/ (`events`). It needs nothing of the case
folder's runs; OpenFOAM is not involved.
"""
