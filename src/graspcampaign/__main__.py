"""``python -m graspcampaign`` runs the command line."""

from graspcampaign.cli.main import main

if __name__ == "__main__":
    main()
